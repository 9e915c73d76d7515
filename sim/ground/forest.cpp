// A stand on the DEM's grid and the laws of a rock meeting it (sources: the header).
#include "sim/ground/forest.h"

#include <cmath>

#include "sim/ground/ground_material.h"

namespace vf {

namespace {
constexpr double kFirEnergyCoefficient = 38.7;  // J / cm^2.31, Dorren and Berger 2006
constexpr double kFirEnergyExponent = 2.31;     // Dorren and Berger 2006
constexpr double kSquareMetresPerHectare = 1e4;
}  // namespace

double stemEnergy(double dbhCm, double speciesFactor) {
  return speciesFactor * kFirEnergyCoefficient * std::pow(dbhCm, kFirEnergyExponent);
}

double stemHitProbability(double stemsPerHectare, double dbhCm, double rockDiameter,
                          double distance) {
  const double perSquareMetre = stemsPerHectare / kSquareMetresPerHectare;
  const double band = rockDiameter + dbhCm / 100.0;  // m
  // -expm1(-x) = 1 - exp(-x) without losing the small chances of a short step.
  return -std::expm1(-perSquareMetre * band * distance);
}

bool Forest::standAt(double x, double y, Stand& out) const {
  const std::int64_t k = nearestSample(*grid, x, y);
  if (k < 0) return false;
  const auto i = static_cast<std::size_t>(k);
  if (!(density[i] > 0)) return false;  // no stems, or no data
  out.stemsPerHectare = density[i];
  out.dbhCm = dbh[i];
  const int c = species.empty() ? 0 : species[i];
  out.speciesFactor =
      c >= 0 && static_cast<std::size_t>(c) < speciesFactor.size() ? speciesFactor[c] : 1.0;
  return true;
}

}  // namespace vf

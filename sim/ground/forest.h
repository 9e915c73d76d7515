// A forest on the DEM's grid (rock fall extension; opt-in with a scene's [forest] table): per DEM
// sample a stem density, a mean stem diameter at breast height (DBH) and optionally a species
// class, and the published laws a statistical rock-tree model needs (forest_law.h applies them).
//
// The laws and where they come from (docs/rockfall.md, "Forest"):
//  - Energy a stem can absorb (Dorren and Berger 2006, Tree Physiology 26:63-71, for silver fir,
//    Abies alba): E = 38.7 DBH^2.31 J, DBH in cm. Rockyfor3D (Dorren 2016, "Rockyfor3D (v5.2)
//    revealed", section 3.4) scales it per species; those species ratios could not be read in
//    a source here, so voxfall takes the factor of each species class from the scene (default 1,
//    the fir of the formula) instead of shipping numbers it cannot cite.
//  - Whether a rock meets a stem: stems stand as a Poisson field of discs (the random stand that
//    a density and a mean DBH describe); a rock of diameter d moving a horizontal distance s
//    sweeps a band of width d + DBH, and meets a stem whose centre lies in that band. The number
//    met is Poisson with mean n (d + DBH) s, n the stems per square metre, so the chance of at
//    least one hit is 1 - exp(-n (d + DBH) s): the mean free path 1 / (n (d + DBH)) of kinetic
//    theory. Rockyfor3D's hit probability depends on the same three quantities (Dorren 2016,
//    section 3.4); its exact expression could not be read here, so this derivation stands in
//    for it.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "sim/shape/heightfield.h"

namespace vf {

// Dorren and Berger 2006: energy a silver fir stem of this DBH absorbs in a central impact
// before it breaks or uproots, E = 38.7 DBH^2.31 J (DBH in cm), times the species' factor.
double stemEnergy(double dbhCm, double speciesFactor = 1.0);

// The chance that a rock of diameter `rockDiameter` (m) meets at least one stem over a horizontal
// distance `distance` (m) through a stand of `stemsPerHectare` stems of diameter `dbhCm` (cm):
// 1 - exp(-n (d + DBH) s), n = stems per m^2.
double stemHitProbability(double stemsPerHectare, double dbhCm, double rockDiameter,
                          double distance);

// A stand on the DEM's samples (the grid of `grid`, each value applying to the DEM cell around
// the sample, as the ground classes do).
struct Forest {
  std::shared_ptr<const Heightfield> grid;  // the DEM whose samples carry the stand
  std::vector<double> density;              // stems per hectare per sample, >= 0 (0: no forest)
  std::vector<double> dbh;                  // mean DBH per sample, cm, >= 0
  std::vector<int> species;                 // class per sample (empty: every stem class 0)
  std::vector<double> speciesFactor;        // per class, the stem energy's factor (>= 0)
  // Stems are hit only by a rock whose centre is less than this above the terrain (m); none:
  // stems taller than any flight.
  std::optional<double> stemHeight;

  // The stand at world (x, y): the nearest sample's; false off the grid or where it has none.
  struct Stand {
    double stemsPerHectare = 0, dbhCm = 0, speciesFactor = 1;
  };
  bool standAt(double x, double y, Stand& out) const;
};

}  // namespace vf

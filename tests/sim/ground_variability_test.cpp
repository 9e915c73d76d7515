// sim/ground/ground_variability: per-cell factors of ground coefficients (r.stone's
// perturbation as its manual describes it: within +-bound of the material's value). Seeds
// reproduce, different seeds and cells differ, every factor lies within the bound, the spread is
// that of a Gaussian of standard deviation bound / 2 truncated at two of them, and with the
// variability off a ground map gives exactly its material's numbers.
#include "sim/ground/ground_variability.h"

#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <numbers>
#include <set>

#include "sim/ground/ground_material.h"
#include "tests/support/test_world.h"

namespace vf {
namespace {

// Field by field, bit for bit.
bool same(const GroundCoefficients& a, const GroundCoefficients& b) {
  return a.law == b.law && a.restitution == b.restitution && a.friction == b.friction &&
         a.rollingResistance == b.rollingResistance &&
         a.tangentialRestitution == b.tangentialRestitution && a.muMin == b.muMin &&
         a.muMax == b.muMax && a.kappa == b.kappa && a.beta == b.beta;
}

GroundMap mapOf(const GroundMaterial& m, double variability, std::uint64_t seed) {
  GroundMap g;
  g.materials.push_back(m);
  g.variability = variability;
  g.variabilitySeed = seed;
  g.cells = std::make_shared<const Heightfield>(test::flatHeightfield(50, 40, 2.0, 0.0));
  return g;
}

TEST(GroundVariability, SameSeedSameFactorsOtherSeedsAndCellsDiffer) {
  constexpr double kBound = 0.1;
  std::set<double> seen;
  for (std::int64_t cell = 0; cell < 200; ++cell) {
    const double f = variabilityFactor(7, cell, GroundCoefficient::kRestitution, kBound);
    EXPECT_EQ(f, variabilityFactor(7, cell, GroundCoefficient::kRestitution, kBound));
    EXPECT_NE(f, variabilityFactor(8, cell, GroundCoefficient::kRestitution, kBound))
        << "cell " << cell;
    EXPECT_NE(f, variabilityFactor(7, cell, GroundCoefficient::kFriction, kBound))
        << "coefficients share a stream, cell " << cell;
    seen.insert(f);
  }
  EXPECT_EQ(seen.size(), 200u) << "cells share a factor";
}

// The bound holds for every draw, and the spread is the documented one: z standard Gaussian
// truncated to [-2, 2] has variance 1 - 4 phi(2) / (2 Phi(2) - 1) = 0.77370 (phi, Phi the
// standard normal density and distribution), so the factor's standard deviation is
// (bound / 2) sqrt(0.77370) = 0.043981 for bound 0.1, and its mean 1. A uniform draw within the
// same bound would give 0.0577, an untruncated Gaussian 0.05. With n = 40,000 draws the sample
// standard deviation has a relative standard error of about sqrt((kurtosis - 1) / (4 n)) < 0.3 %
// (the truncated Gaussian's kurtosis is below 3), and the mean a standard error of 0.00022:
// the tolerances are five of them.
TEST(GroundVariability, FactorsLieWithinTheBoundWithTheTruncatedGaussianSpread) {
  constexpr double kBound = 0.1;
  constexpr int n = 40000;
  double sum = 0, sumSq = 0, lo = 2, hi = 0;
  for (int k = 0; k < n; ++k) {
    const double f = variabilityFactor(3, k, GroundCoefficient::kMuMax, kBound);
    lo = std::min(lo, f);
    hi = std::max(hi, f);
    sum += f;
    sumSq += f * f;
  }
  EXPECT_GE(lo, 1 - kBound);
  EXPECT_LE(hi, 1 + kBound);
  EXPECT_LT(lo, 1 - 0.95 * kBound) << "the tails near the bound are never reached";
  EXPECT_GT(hi, 1 + 0.95 * kBound);
  const double mean = sum / n, sd = std::sqrt(sumSq / n - mean * mean);
  const double phi2 = std::exp(-2.0) / std::sqrt(2 * std::numbers::pi);
  const double mass = std::erf(2.0 / std::sqrt(2.0));  // 2 Phi(2) - 1
  const double expected = kBound / 2 * std::sqrt(1 - 4 * phi2 / mass);
  EXPECT_NEAR(expected, 0.043981, 1e-6);  // the number in the comment above
  EXPECT_NEAR(mean, 1.0, 5 * 0.00022);
  EXPECT_NEAR(sd / expected, 1.0, 5 * 0.003);
}

// Which coefficients vary is the law's: the STONE law's four, the slip law's five; the others
// are left alone. Restitutions stay <= 1, mu_max >= mu_min.
TEST(GroundVariability, EveryCoefficientOfTheLawInForceVariesWithinTheBound) {
  constexpr double kBound = 0.1;
  GroundMaterial stone = *groundPreset("glacial_deposits", 0.8);
  GroundMaterial slip = *groundPreset("leine2014_demo", 0.8);
  slip.restitution = 0.2;  // the preset's 0 would stay 0 (relative factors)
  int stoneMoved[4] = {}, slipMoved[5] = {};
  for (std::int64_t cell = 0; cell < 300; ++cell) {
    const GroundCoefficients s = perturbedCoefficients(stone, kBound, 11, cell);
    const double sv[4] = {s.restitution, s.friction, s.rollingResistance, s.tangentialRestitution};
    const double s0[4] = {stone.restitution, stone.friction, stone.rollingResistance,
                          stone.tangentialRestitution};
    for (int k = 0; k < 4; ++k) {
      EXPECT_LE(std::abs(sv[k] - s0[k]), kBound * s0[k] * (1 + 1e-12)) << "stone " << k;
      stoneMoved[k] += sv[k] != s0[k];
    }
    EXPECT_EQ(s.muMin, stone.muMin);
    EXPECT_EQ(s.kappa, stone.kappa);
    const GroundCoefficients p = perturbedCoefficients(slip, kBound, 11, cell);
    const double pv[5] = {p.restitution, p.muMin, p.muMax, p.kappa, p.beta};
    const double p0[5] = {slip.restitution, slip.muMin, slip.muMax, slip.kappa, slip.beta};
    for (int k = 0; k < 5; ++k) {
      EXPECT_LE(std::abs(pv[k] - p0[k]), kBound * p0[k] * (1 + 1e-12)) << "slip " << k;
      slipMoved[k] += pv[k] != p0[k];
    }
    EXPECT_EQ(p.friction, slip.friction);
    EXPECT_EQ(p.rollingResistance, slip.rollingResistance);
    EXPECT_EQ(p.law, GroundLawKind::kSlip);
  }
  for (int k = 0; k < 4; ++k) EXPECT_EQ(stoneMoved[k], 300) << "stone coefficient " << k;
  for (int k = 0; k < 5; ++k) EXPECT_EQ(slipMoved[k], 300) << "slip coefficient " << k;

  // Clipping: a restitution of 1 never exceeds 1; equal mu_min and mu_max never cross.
  GroundMaterial edge = slip;
  edge.restitution = 1.0;
  edge.muMax = edge.muMin;
  for (std::int64_t cell = 0; cell < 300; ++cell) {
    const GroundCoefficients p = perturbedCoefficients(edge, kBound, 5, cell);
    EXPECT_LE(p.restitution, 1.0);
    EXPECT_GE(p.muMax, p.muMin);
  }
}

TEST(GroundVariability, AMapPerturbsPerCellAndOffIsExactlyTheMaterial) {
  const GroundMaterial m = *groundPreset("ramms_chant_sura", 0.8);
  const GroundMap off = mapOf(m, 0.0, 1), on = mapOf(m, 0.1, 1), other = mapOf(m, 0.1, 2);
  // Off: the material's numbers, bit for bit, everywhere.
  EXPECT_TRUE(same(off.coefficientsAt(13.1, 27.9), m));
  // On: the cell of the nearest sample, so two points of one cell agree and neighbours differ.
  // Sample (6, 14) is at (12, 28); its cell spans x 11..13, y 27..29.
  const GroundCoefficients a = on.coefficientsAt(12.9, 27.1), b = on.coefficientsAt(11.2, 28.8);
  EXPECT_TRUE(same(a, b));
  EXPECT_TRUE(same(a, perturbedCoefficients(m, 0.1, 1, 14 * 50 + 6)));
  EXPECT_FALSE(same(a, on.coefficientsAt(13.1, 27.1)));
  EXPECT_FALSE(same(a, other.coefficientsAt(12.9, 27.1))) << "the seed changes nothing";
  // Off the grid: the material as it is.
  EXPECT_TRUE(same(on.coefficientsAt(-5, 10), m));
  EXPECT_TRUE(same(on.coefficientsAt(200, 10), m));
}

}  // namespace
}  // namespace vf

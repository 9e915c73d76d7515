// Block sizes: volumes drawn from the bounded log-normal and power laws against their
// closed-form quantiles, shapes resized to them against the scaling laws of mass properties
// (mass ~ s^3, inertia ~ s^5, diameter ~ s), and an ensemble whose rocks carry the drawn mass.
#include "sim/ensemble/block_size.h"

#include <gtest/gtest.h>

#include <cmath>
#include <set>

#include "sim/core/prng.h"
#include "sim/ensemble/ensemble.h"
#include "sim/shape/shape.h"
#include "tests/support/chute_dem.h"
#include "tests/support/test_world.h"

namespace vf {
namespace {

VolumeSpec logNormal(double median, double sigma, double min, double max) {
  VolumeSpec v;
  v.law = VolumeSpec::Law::kLogNormal;
  v.median = median, v.sigma = sigma, v.min = min, v.max = max;
  return v;
}

VolumeSpec power(double b, double min, double max) {
  VolumeSpec v;
  v.law = VolumeSpec::Law::kPower;
  v.exponent = b, v.min = min, v.max = max;
  return v;
}

// With bounds far in the tails the log-normal's quantiles are exp(mu + sigma z_p): the median
// at u = 1/2, and at u = Phi(1) = 0.841344746 the volume median * e^sigma. The bisection stops
// at the spacing of doubles, so the only error is the bounds' truncation (Phi(-12) ~ 1e-33).
TEST(BlockSize, LogNormalVolumesFollowTheirQuantiles) {
  const VolumeSpec v = logNormal(0.5, 0.8, 0.5 * std::exp(-12 * 0.8), 0.5 * std::exp(12 * 0.8));
  EXPECT_NEAR(volumeAt(v, 0.5), 0.5, 1e-12);
  EXPECT_NEAR(volumeAt(v, 0.5 * std::erfc(-1 / std::sqrt(2.0))), 0.5 * std::exp(0.8), 1e-12);
  EXPECT_NEAR(volumeAt(v, 0.5 * std::erfc(2 / std::sqrt(2.0))), 0.5 * std::exp(-1.6), 1e-12);
}

// Truncated to [min, max], u = 0 gives min, u -> 1 gives max, and the median of the truncated
// law is where the normal's probability is halfway between its values at the bounds.
TEST(BlockSize, LogNormalVolumesStayWithinTheirBounds) {
  const VolumeSpec v = logNormal(1.0, 1.0, 0.5, 4.0);
  EXPECT_NEAR(volumeAt(v, 0), 0.5, 1e-12);
  EXPECT_NEAR(volumeAt(v, std::nextafter(1.0, 0.0)), 4.0, 1e-9);
  const auto phi = [](double z) { return 0.5 * std::erfc(-z / std::sqrt(2.0)); };
  const double pMid = 0.5 * (phi(std::log(0.5)) + phi(std::log(4.0)));
  const double vMid = volumeAt(v, 0.5);
  EXPECT_NEAR(phi(std::log(vMid)), pMid, 1e-12);
}

// Power law: the fraction of volumes above V is (V^-b - max^-b) / (min^-b - max^-b); checked
// on an even grid of u (no sampling noise: u is the probability itself).
TEST(BlockSize, PowerLawVolumesExceedVAsTheLawSays) {
  const double b = 0.5, lo = 0.01, hi = 100;
  const VolumeSpec v = power(b, lo, hi);
  const int n = 100000;
  for (double V : {0.05, 1.0, 20.0}) {
    int above = 0;
    for (int k = 0; k < n; ++k) above += volumeAt(v, (k + 0.5) / n) > V;
    const double expected =
        (std::pow(V, -b) - std::pow(hi, -b)) / (std::pow(lo, -b) - std::pow(hi, -b));
    EXPECT_NEAR(above / static_cast<double>(n), expected, 1.0 / n) << "V = " << V;
  }
  EXPECT_NEAR(volumeAt(v, 0), lo, 1e-12);
}

TEST(BlockSize, AResizedShapeScalesItsMassPropertiesAndTree) {
  const auto base = test::boxShape(1.0, 0.5, 0.25, 2000, 4);
  const double s = 2;  // twice the size
  const auto big = resizedShape(*base, base->volume * s * s * s, 3000);
  EXPECT_NEAR(big->volume, base->volume * 8, 1e-12);
  EXPECT_NEAR(big->mass, 3000 * base->volume * 8, 1e-9);
  const double inertiaScale = (3000.0 / 2000.0) * std::pow(s, 5);
  EXPECT_NEAR(big->inertiaBody(0, 0), base->inertiaBody(0, 0) * inertiaScale, 1e-9);
  EXPECT_NEAR(big->inertiaBody(2, 2), base->inertiaBody(2, 2) * inertiaScale, 1e-9);
  EXPECT_NEAR(big->diameter, base->diameter * s, 1e-12);
  EXPECT_NEAR(big->stepRadius(), base->stepRadius() * s, 1e-12);
  ASSERT_EQ(big->tree->levels.size(), base->tree->levels.size());
  const auto& a = base->tree->leaves();
  const auto& c = big->tree->leaves();
  ASSERT_EQ(a.centers.size(), c.centers.size());
  EXPECT_NEAR(c.radius, a.radius * s, 1e-15);
  EXPECT_NEAR((c.centers[7] - a.centers[7] * s).norm(), 0, 1e-12);
  EXPECT_NEAR((big->meshOrigin - base->meshOrigin * s).norm(), 0, 1e-12);
}

class BlockSizeEnsembleTest : public test::ChuteFolderTest {};

// Every realisation's rock has the volume its size generator draws and the mass that volume
// and the drawn density give; a second source's own distribution applies to its rocks.
TEST_F(BlockSizeEnsembleTest, RocksCarryTheirDrawnVolumeAndMass) {
  test::writeChuteScene(
      dir_,
      "shape = \"rock\"\n"
      "volume = { distribution = \"power\", exponent = 0.7, min = 0.05, max = 2.0 }\n"
      "density = [2400, 2900]\n"
      "[[ensemble.release]]\nline = [[1005.0, 5006.3], [1005.0, 5017.7]]\n"
      "[[ensemble.release]]\npoints = [[1005.0, 5012.0]]\n"
      "volume = { distribution = \"lognormal\", median = 5.0, sigma = 0.1, min = 4.0, max = 6.0 "
      "}\n",
      0.5);
  const Ensemble e(loadScene((dir_ / "scene.toml").string()));
  std::set<double> volumes;
  int fromPoint = 0;
  for (int i = 0; i < 12; ++i) {
    const RealisationResult r = e.run(i, realisationSeed(2, i), false);
    const double density = r.mass / r.volume;
    EXPECT_GE(density, 2400 - 1e-9);
    EXPECT_LE(density, 2900 + 1e-9);
    const bool big = r.volume >= 4.0 - 1e-9;
    EXPECT_TRUE(big || (r.volume >= 0.05 - 1e-12 && r.volume <= 2.0 + 1e-12)) << r.volume;
    fromPoint += big;
    volumes.insert(r.volume);
  }
  EXPECT_GT(fromPoint, 0);
  EXPECT_LT(fromPoint, 12);
  EXPECT_EQ(volumes.size(), 12u);  // drawn, not the mesh's own size
}

}  // namespace
}  // namespace vf

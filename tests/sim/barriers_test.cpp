// Barriers: a rock flying without gravity at a barrier over flat ground hits the barrier's real
// geometry (its static pieces) and the capacity rule decides: under the capacity it stops there;
// over it, the barrier fails and the rock goes on with its energy at the hit (0.5 m v^2, known
// in closed form) less the capacity, to rounding.
#include "sim/ground/barriers.h"

#include <gtest/gtest.h>

#include "sim/scene/scene.h"
#include "tests/support/test_world.h"

namespace vf {
namespace {

constexpr double kSide = 0.5, kDensity = 2600, kSpeed = 10;
constexpr double kMass = kDensity * kSide * kSide * kSide;
constexpr double kEnergy = 0.5 * kMass * kSpeed * kSpeed;  // J, no spin
constexpr double kWallX = 20, kThickness = 0.3;

struct Outcome {
  Vec3 x = Vec3::Zero();
  double energy = 0;  // J, kinetic, after the run
  BarrierResult result;
};

Outcome throwAtBarrier(double capacity) {
  auto flat = std::make_shared<Heightfield>();
  flat->nx = 41, flat->ny = 21, flat->cell = 1;
  flat->z.assign(static_cast<std::size_t>(flat->nx * flat->ny), 0.0);
  WorldDef def;
  def.gravity = Vec3::Zero();
  def.terrain = flat;
  test::RockFallWorld withRockFall(def, {});  // with the rock monitor, as a scene on terrain has
  World& w = withRockFall.world;
  BodyDef rock;
  rock.shape = test::boxShape(kSide, kSide, kSide, kDensity, 4);
  rock.position = Vec3(5, 10, 1.5);
  rock.velocity = Vec3(kSpeed, 0, 0);
  w.addBody(rock);
  const Barrier net{"net", {{kWallX, 2.0}, {kWallX, 18.0}}, 3.0, capacity, kThickness};
  const auto monitor = attachBarriers(w, {net}, {barrierPieces(net, *flat, 4)});
  w.advanceTo(2.5);  // 15 m to the wall at 10 m/s, then 1 s on
  Outcome o;
  o.x = w.state(0).x;
  o.energy =
      0.5 * kMass * w.velocity(0).squaredNorm() + 0.5 * w.state(0).L.dot(w.angularVelocity(0));
  o.result = monitor->results()[0];
  return o;
}

TEST(Barriers, ARockUnderTheCapacityStopsAtTheBarrier) {
  const Outcome o = throwAtBarrier(2 * kEnergy);
  EXPECT_EQ(o.result.hits, 1);
  EXPECT_EQ(o.result.stopped, 1);
  EXPECT_EQ(o.result.passed, 0);
  EXPECT_FALSE(o.result.failed);
  EXPECT_NEAR(o.result.maxEnergy, kEnergy, 1e-9 * kEnergy);
  EXPECT_EQ(o.energy, 0.0);
  // In front of the wall: its centre at most half its diagonal from the wall's face.
  EXPECT_LT(o.x.x(), kWallX - kThickness / 2);
  EXPECT_GT(o.x.x(), kWallX - kThickness / 2 - kSide);
}

TEST(Barriers, ARockOverTheCapacityPassesWithTheExcess) {
  const Outcome o = throwAtBarrier(0.25 * kEnergy);
  EXPECT_EQ(o.result.hits, 1);
  EXPECT_EQ(o.result.stopped, 0);
  EXPECT_EQ(o.result.passed, 1);
  EXPECT_TRUE(o.result.failed);
  EXPECT_NEAR(o.result.maxEnergy, kEnergy, 1e-9 * kEnergy);
  EXPECT_NEAR(o.energy, 0.75 * kEnergy, 1e-9 * kEnergy);
  EXPECT_GT(o.x.x(), kWallX + kThickness / 2 + kSide);
}

TEST(Barriers, PiecesStandOnTheGroundUpToTheHeight) {
  auto slope = std::make_shared<Heightfield>();
  slope->nx = 11, slope->ny = 11, slope->cell = 1;
  for (int j = 0; j < 11; ++j)
    for (int i = 0; i < 11; ++i) slope->z.push_back(0.5 * i);  // rises 0.5 m per m along x
  const Barrier b{"b", {{2.0, 5.0}, {8.0, 5.0}}, 2.0, 100, kThickness};
  const auto pieces = barrierPieces(b, *slope, 3);
  ASSERT_EQ(pieces.size(), 3u);  // 6 m in pieces no longer than the 2 m height
  for (const BarrierPiece& p : pieces) {
    const Eigen::AlignedBox3d box = p.shape->mesh.bounds();
    const double x = p.position.x();
    // Top: the ground at the piece's middle plus the height; bottom: kBarrierEmbed under the
    // lowest ground of the piece (its uphill-facing end, 1 m before its middle).
    EXPECT_NEAR(p.position.z() + box.max().z(), 0.5 * x + 2.0, 1e-9);
    EXPECT_NEAR(p.position.z() + box.min().z(), 0.5 * (x - 1) - kBarrierEmbed, 1e-9);
  }
}

}  // namespace
}  // namespace vf

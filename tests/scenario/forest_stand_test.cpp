// Rocks rolling through a stand (sim/ground/forest_law.h) in a whole World: a dense stand stops
// a rock sooner than none, a stand of zero density is the same run as no forest to the bit, and
// the hits do not depend on the thread count.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>

#include "sim/ground/forest.h"
#include "sim/ground/forest_law.h"
#include "sim/ground/ground_material.h"
#include "sim/world.h"
#include "tests/support/smooth_ball.h"
#include "tests/support/test_world.h"

namespace vf {
namespace {

constexpr double kG = 9.81;
constexpr double kV0 = 8.0;   // m/s
constexpr double kMuR = 0.3;  // rolling resistance

// Flat terrain 61 x 11 samples of 1 m at z = 0, STONE's rolling resistance kMuR: the world's
// settings and rock fall's.
struct Ground {
  WorldDef world;
  RockFallDef rockFall;
};

Ground rollingGround() {
  Ground ground;
  ground.world.terrain =
      std::make_shared<const Heightfield>(test::flatHeightfield(61, 11, 1.0, 0.0));
  auto g = std::make_shared<GroundMap>();
  GroundMaterial m;
  m.name = "test";
  m.restitution = 0;
  m.friction = 0.8;
  m.rollingResistance = kMuR;
  g->materials.push_back(m);
  ground.rockFall.ground = g;
  return ground;
}

std::shared_ptr<const Forest> stand(const Ground& ground, double stemsPerHectare, double dbhCm) {
  auto f = std::make_shared<Forest>();
  f->grid = ground.world.terrain;
  f->density.assign(ground.world.terrain->z.size(), stemsPerHectare);
  f->dbh.assign(ground.world.terrain->z.size(), dbhCm);
  return f;
}

// A 1 m smooth ball (1400 kg) rolling without slip at kV0 towards +x from x = 5; returns the
// world after 10 s (it stops within 7 v0^2 / (10 mu_r g) = 15.2 m on bare ground, in 3.9 s).
std::unique_ptr<test::RockFallWorld> roll(const Ground& ground) {
  auto rock = std::make_unique<test::RockFallWorld>(ground.world, ground.rockFall);
  BodyDef b;
  b.shape = test::smoothBall(0.5, 1400);
  b.position = Vec3(5, 5, 0.5);
  b.velocity = Vec3(kV0, 0, 0);
  b.angularVelocity = Vec3(0, kV0 / 0.5, 0);
  rock->world.addBody(b);
  rock->world.advanceTo(10.0);
  return rock;
}

}  // namespace

// The bare run stops at the Azzoni distance (checked in rockfall_test); a stand of 2000 stems/ha
// of DBH 30 cm (100 kJ a stem, more than the ball's 62.7 kJ: one hit stops it) has a mean free
// path of 1 / (0.2 * 1.3) = 3.8 m, so a hit within the 15.2 m is all but certain (98 %) for any
// seed. Every seed of ten stops sooner, each after at least one hit.
TEST(ForestStand, ADenseStandStopsARockSoonerThanNone) {
  const double bare = roll(rollingGround())->world.state(0).x.x() - 5;
  EXPECT_NEAR(bare, 7 * kV0 * kV0 / (10 * kMuR * kG), 0.5);
  for (std::uint64_t seed = 1; seed <= 10; ++seed) {
    Ground def = rollingGround();
    def.rockFall.forest = stand(def, 2000, 30);
    def.rockFall.forestSeed = seed;
    const auto world = roll(def);
    EXPECT_LT(world->world.state(0).x.x() - 5, bare - 1.0) << "seed " << seed;
    EXPECT_GE(world->rockFall.treeHits(0).hits, 1) << "seed " << seed;
    EXPECT_LT(world->world.velocity(0).norm(), 0.1) << "seed " << seed;
  }
}

// Zero density everywhere: the same states after every step as with no forest (the checksum).
TEST(ForestStand, ZeroDensityIsTheRunWithoutForest) {
  Ground def = rollingGround();
  const std::uint64_t bare = roll(def)->world.stepsHash();
  def.rockFall.forest = stand(def, 0, 30);
  const auto world = roll(def);
  EXPECT_EQ(world->world.stepsHash(), bare);
  EXPECT_EQ(world->rockFall.treeHits(0).hits, 0);
}

// The same seed gives the same hits whatever the thread count; another seed other hits.
TEST(ForestStand, HitsDependOnTheSeedNotOnTheThreads) {
  Ground def = rollingGround();
  def.rockFall.forest = stand(def, 300, 20);  // 39 kJ a stem: several hits before the ball stops
  def.rockFall.forestSeed = 5;
  const auto one = roll(def);
  def.world.threads = 2;
  const auto two = roll(def);
  EXPECT_EQ(one->world.stepsHash(), two->world.stepsHash());
  EXPECT_EQ(one->rockFall.treeHits(0).hits, two->rockFall.treeHits(0).hits);
  bool differs = false;
  for (std::uint64_t seed = 6; seed < 10 && !differs; ++seed) {
    def.rockFall.forestSeed = seed;
    differs = roll(def)->world.stepsHash() != one->world.stepsHash();
  }
  EXPECT_TRUE(differs);
}

}  // namespace vf

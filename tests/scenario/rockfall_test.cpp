// Rock fall on terrain: ground materials, rolling resistance, terrain edges and holes.
// Each tolerance is derived from the method (step dt, voxel level) in the comment beside it.
#include <gtest/gtest.h>

#include <cmath>

#include "sim/core/prng.h"
#include "sim/ground/ground_material.h"
#include "sim/ground/rock_monitor.h"
#include "sim/solve/ground_law.h"
#include "sim/world.h"
#include "tests/support/smooth_ball.h"
#include "tests/support/test_world.h"

namespace vf {
namespace {

constexpr double kG = 9.81;

std::shared_ptr<const GroundMap> oneMaterial(double restitution, double friction, double rolling,
                                             double tangential = 1.0) {
  auto g = std::make_shared<GroundMap>();
  GroundMaterial m;
  m.name = "test";
  m.restitution = restitution;
  m.friction = friction;
  m.rollingResistance = rolling;
  m.tangentialRestitution = tangential;
  g->materials.push_back(m);
  return g;
}

}  // namespace

// A sphere rolling without slip on level ground with rolling resistance mu_r stops after
// d = 7 v0^2 / (10 mu_r g) (Azzoni et al. 1995: v0^2 / (2 A mu_r g), A = 5/7 for a solid
// sphere).
TEST(Rockfall, RollingSphereStopsAtTheRollingResistanceDistance) {
  const double r = 0.25, v0 = 2.0, muR = 0.3;
  const double d = 7 * v0 * v0 / (10 * muR * kG);
  auto ball = test::smoothBall(r, 100);
  WorldDef def;
  def.groundHeight = 0.0;
  test::RockFallWorld rock(def, test::groundLaws(oneMaterial(0.0, 0.8, muR)));
  World& world = rock.world;
  BodyDef b;
  b.shape = ball;
  b.position = Vec3(0, 0, r);
  b.velocity = Vec3(v0, 0, 0);
  b.angularVelocity = Vec3(0, v0 / r, 0);  // rolling without slip towards +x
  world.addBody(b);
  const double tStop = v0 / (5.0 / 7.0 * muR * kG);
  world.advanceTo(tStop + 1.0);
  const double dt = world.totals().dtMax;
  // Tolerance: per step the brake takes mu_r r N dt of angular momentum about the contact and
  // friction converts it into speed one step later, so the speed lags the closed form by one
  // step of deceleration (a dt) and the position integrates it with Euler's v0 dt / 2, as in
  // the Coulomb sliding test; 2 v0 dt covers both.
  EXPECT_NEAR(world.state(0).x.x(), d, 2 * v0 * dt);
  EXPECT_LT(world.velocity(0).norm(), kG * dt) << "at rest: below what gravity adds in a step";
  EXPECT_NEAR(world.state(0).x.y(), 0, 1e-9);
  // Without rolling resistance (the paper's model) the same ball rolls on (it keeps over 99 %
  // of v0 over the same time): the stop above is the rolling law's doing.
  WorldDef paper;
  paper.groundHeight = 0.0;
  paper.contact.restitutionBodyGround = 0.0;
  World free(paper);
  free.addBody(b);
  free.advanceTo(tStop + 1.0);
  EXPECT_GT(free.velocity(0).x(), 0.99 * v0);
  EXPECT_GT(free.state(0).x.x(), 3 * d);
}

// STONE's modes (sim/solve/ground_law.cpp). A ball rolling without slip at v0 = 2 m/s drops
// h = 0.5 m onto level ground (restitution 0, Rt = 0.5): the landing is 0.8 m from the release
// at 3.7 m/s, under STONE's 3 m and 5 m/s, so it is no bounce but the start of rolling. Its
// contact point does not slip, so friction takes nothing, and it rolls the Azzoni distance
// from where it landed. Were the landing a bounce, Rt would halve its speed (a quarter of the
// distance); were the landing's impulse (m sqrt(2 g h), 300 times a step's weight) fed to the
// rolling brake, its spin would end there and friction would take 2/7 of its speed.
TEST(Rockfall, AShortSlowLandingRollsOnWithNoBounceLoss) {
  const double r = 0.25, v0 = 2.0, muR = 0.3, h = 0.5;
  const double tFall = std::sqrt(2 * h / kG);
  const double d = v0 * tFall + 7 * v0 * v0 / (10 * muR * kG);
  WorldDef def;
  def.groundHeight = 0.0;
  test::RockFallWorld rock(def, test::groundLaws(oneMaterial(0.0, 0.8, muR, 0.5)));
  World& world = rock.world;
  BodyDef b;
  b.shape = test::smoothBall(r, 100);
  b.position = Vec3(0, 0, r + h);
  b.velocity = Vec3(v0, 0, 0);
  b.angularVelocity = Vec3(0, v0 / r, 0);
  world.addBody(b);
  world.advanceTo(tFall + v0 / (5.0 / 7.0 * muR * kG) + 1.0);
  const double dt = world.totals().dtMax;
  // Tolerance: the rolling test's 2 v0 dt, plus v0 dt for the landing, which happens within
  // one step of the closed-form time.
  EXPECT_NEAR(world.state(0).x.x(), d, 3 * v0 * dt);
  EXPECT_LT(world.velocity(0).norm(), kG * dt) << "at rest: below what gravity adds in a step";
}

// A landing faster than 5 m/s is a bounce: a ball without spin moving at 8 m/s lands from 2 m
// (10.2 m/s). The reference is the same landing with Rt = 1 (eq. 15 and Coulomb friction only,
// which leave it with v_ref < v0 and spin w_ref). With Rt = 0.5 the bounce keeps 0.5 v0 of the
// tangential velocity, and the spin is scaled by the same factor 0.5 v0 / v_ref; with Rt = 0.9
// (0.9 v0 > v_ref) friction has already taken more, and nothing changes: not a bit.
TEST(Rockfall, AFastLandingBouncesKeepingAtMostRtOfTheTangentialVelocity) {
  const double r = 0.25, v0 = 8.0, h = 2.0, rn = 0.3;
  struct Landing {
    Vec3 v, w;
  };
  auto land = [&](double rt) {
    WorldDef def;
    def.groundHeight = 0.0;
    test::RockFallWorld rock(def, test::groundLaws(oneMaterial(rn, 0.8, 0.0, rt)));
    World& world = rock.world;
    BodyDef b;
    b.shape = test::smoothBall(r, 100);
    b.position = Vec3(0, 0, r + h);
    b.velocity = Vec3(v0, 0, 0);
    world.addBody(b);
    world.stepNext();  // starts falling
    while (world.velocity(0).z() < 0 && world.time() < 2.0) world.stepNext();
    return Landing{world.velocity(0), world.angularVelocity(0)};
  };
  const Landing ref = land(1.0), half = land(0.5), most = land(0.9);
  ASSERT_GT(ref.v.z(), 0) << "it bounced";
  ASSERT_LT(ref.v.x(), 0.9 * v0);
  ASSERT_GT(ref.v.x(), 0.5 * v0);
  // The cap scales the tangential velocity and the spin: exact to rounding.
  EXPECT_NEAR(half.v.x(), 0.5 * v0, 1e-12 * v0);
  EXPECT_NEAR(half.w.y(), ref.w.y() * 0.5 * v0 / ref.v.x(), 1e-12 * v0 / r);
  EXPECT_EQ(half.v.z(), ref.v.z()) << "the normal velocity is eq. 15's";
  EXPECT_EQ(most.v, ref.v);
  EXPECT_EQ(most.w, ref.w);
}

// The lift-off test of the rolling mode: a body is clear of the floor plane and of terrain
// (here level at z = 0.5) when every leaf sphere is, by its centre's height less its radius.
// Two leaves of radius 0.05 at z = 1.1 and 0.8: the lower is 0.75 above the floor and 0.25
// above the terrain, whichever leaf the hint names; on a slope, along its normal.
TEST(Rockfall, ClearOfGroundTestsEveryLeafsGap) {
  auto shape = std::make_shared<Shape>();
  auto tree = std::make_shared<SphereTree>();
  SphereTreeLevel leaves;
  leaves.radius = 0.05;
  leaves.edge = 2 * leaves.radius / std::sqrt(3.0);
  leaves.centers = {Vec3(0, 0, 0.1), Vec3(0, 0, -0.2)};
  leaves.childBegin = {0, 0, 0};
  tree->levels = {leaves};
  finishSphereTree(*tree);
  shape->tree = tree;
  BodyInfo b;
  b.shape = shape;
  BodyState y;
  y.x = Vec3(3.2, 4.1, 1.0);
  auto terrain = std::make_shared<Heightfield>(test::flatHeightfield(10, 10, 1.0, 0.5));
  const double eps = 1e-9;
  for (std::uint32_t hint : {0u, 1u, 1000000u}) {  // any hint, even out of range
    std::uint32_t h = hint;
    EXPECT_TRUE(clearOfGround(b, y, nullptr, 0.0, 0.75 - eps, h)) << hint;
    EXPECT_FALSE(clearOfGround(b, y, nullptr, 0.0, 0.75 + eps, h)) << hint;
    EXPECT_TRUE(clearOfGround(b, y, terrain.get(), std::nullopt, 0.25 - eps, h)) << hint;
    EXPECT_FALSE(clearOfGround(b, y, terrain.get(), std::nullopt, 0.25 + eps, h)) << hint;
    EXPECT_FALSE(clearOfGround(b, y, terrain.get(), 0.0, 0.25 + eps, h)) << "the nearer";
    EXPECT_TRUE(clearOfGround(b, y, terrain.get(), 0.0, 0.25 - eps, h)) << "of both";
    // The leaf found within is where the next call starts: the lower one.
    std::uint32_t found = hint;
    EXPECT_FALSE(clearOfGround(b, y, nullptr, 0.0, 0.75 + eps, found));
    EXPECT_EQ(found, 1u) << hint;
  }
  y.x = Vec3(30, 4.1, 1.0);  // off the grid, no floor: nothing below
  std::uint32_t h = 0;
  EXPECT_TRUE(clearOfGround(b, y, terrain.get(), std::nullopt, 1e9, h));

  // On a 45-degree slope (z = x) the gap is measured along the normal: the lower leaf, 1.0
  // above the surface at z = 4.2, is 1 / sqrt(2) - 0.05 from it; 0.95 vertically.
  Heightfield slope;
  slope.nx = slope.ny = 10;
  slope.cell = 1;
  for (int j = 0; j < 10; ++j)
    for (int i = 0; i < 10; ++i) slope.z.push_back(i);
  y.x = Vec3(3.2, 4.1, 4.4);
  const double gap = 1 / std::sqrt(2.0) - 0.05;
  EXPECT_TRUE(clearOfGround(b, y, &slope, std::nullopt, gap - eps, h));
  EXPECT_FALSE(clearOfGround(b, y, &slope, std::nullopt, gap + eps, h));
}

// The same through a real sphere tree (a 0.4 x 0.3 x 0.2 m box at level 4, 8 x 8 rough
// terrain of 0.5 m cells with a hole, sometimes a floor, random poses): against brute force
// over every leaf, the least gap g, it must call the body clear at g - 1e-7 and not at
// g + 1e-7 (its node bounds pass over subtrees only with 1e-9 m to spare), whatever the hint.
TEST(Rockfall, ClearOfGroundAgreesWithTheLeastGapOfAllLeaves) {
  BodyInfo b;
  b.shape =
      makeShape("box", test::boxMesh(Vec3(0, 0, 0), Vec3(0.4, 0.3, 0.2)), Vec3::Ones(), 1000, 4);
  const SphereTreeLevel& leaves = b.shape->tree->leaves();
  Prng rng(41);
  Heightfield rough;
  rough.nx = rough.ny = 8;
  rough.cell = 0.5;
  for (int s = 0; s < 64; ++s) rough.z.push_back(rng.uniform(0, 0.6));
  rough.z[27] = NAN;  // sample (3, 3): a hole of four cells
  int clearCases = 0;
  for (int k = 0; k < 300; ++k) {
    BodyState y;
    y.x = Vec3(rng.uniform(-0.3, 3.8), rng.uniform(-0.3, 3.8), rng.uniform(0.3, 1.2));
    y.q = Quat(Eigen::AngleAxisd(
        rng.uniform(0, 6.3),
        Vec3(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(0.1, 1)).normalized()));
    const std::optional<double> floor =
        k % 3 == 0 ? std::optional<double>(rng.uniform(0, 0.8)) : std::nullopt;
    double least = INFINITY;
    const Mat3 R = y.q.toRotationMatrix();
    for (const Vec3& c0 : leaves.centers) {
      const Vec3 c = y.x + R * c0;
      if (floor) least = std::min(least, c.z() - *floor - leaves.radius);
      const double h = rough.heightAt(c.x(), c.y());
      if (!std::isnan(h))
        least = std::min(least, (c.z() - h) * rough.normalAt(c.x(), c.y()).z() - leaves.radius);
    }
    if (!std::isfinite(least)) continue;
    std::uint32_t hint = static_cast<std::uint32_t>(rng.uniform(0, 2 * leaves.centers.size()));
    EXPECT_TRUE(clearOfGround(b, y, &rough, floor, least - 1e-7, hint)) << k;
    EXPECT_FALSE(clearOfGround(b, y, &rough, floor, least + 1e-7, hint)) << k;
    ++clearCases;
  }
  EXPECT_GT(clearCases, 250);
}

// Flat terrain at z = 0: nx x ny samples of 1 m from (0, 0); NaN samples are NODATA.
std::shared_ptr<const Heightfield> flatTerrain(int nx, int ny,
                                               std::vector<std::pair<int, int>> holes = {}) {
  auto h = std::make_shared<Heightfield>(test::flatHeightfield(nx, ny, 1.0, 0.0));
  for (auto [i, j] : holes) h->z[static_cast<std::size_t>(j) * nx + i] = NAN;
  return h;
}

// A smooth ball rolling at 3 m/s towards the east edge of a 20 m grid (no floor plane).
test::RockFallWorld rollTowardsEdge(TerrainEdge edge) {
  WorldDef def;
  def.terrain = flatTerrain(21, 21);
  def.contact.restitutionBodyGround = 0;
  RockFallDef edgePolicy;
  edgePolicy.terrainEdge = edge;
  test::RockFallWorld rock(def, edgePolicy);
  World& world = rock.world;
  BodyDef b;
  b.shape = test::smoothBall(0.25, 100);
  b.position = Vec3(10, 10, 0.25);
  b.velocity = Vec3(3, 0, 0);
  b.angularVelocity = Vec3(0, 3 / 0.25, 0);
  world.addBody(b);
  return rock;
}

TEST(Rockfall, ARockRolledOffTheGridEdgeIsRemovedAndRecorded) {
  test::RockFallWorld rock = rollTowardsEdge(TerrainEdge::kAuto);  // no plane: remove
  World& world = rock.world;
  world.advanceTo(5.0);
  ASSERT_EQ(rock.rockFall.outcomes().size(), 1u);
  const RockOutcome& r = rock.rockFall.outcomes()[0];
  EXPECT_EQ(r.state, RockState::kLeft);
  EXPECT_FALSE(world.isActive(0));
  // Its centre crosses x = 20 after (20 - 10) / 3 s; it is removed in the step it does, at
  // most one step (and 3 m/s times it) later.
  const double dt = world.totals().dtMax;
  EXPECT_NEAR(r.endTime, 10.0 / 3.0, 2 * dt);
  EXPECT_NEAR(r.end.x(), 20.0, 3 * 2 * dt);
  EXPECT_NE(r.message.find("body 0 left the terrain grid"), std::string::npos) << r.message;
  EXPECT_EQ(world.measure().tunnelled, 0);  // gone, not tunnelled
  EXPECT_TRUE(rock.allSettled());
  // It does not fall forever: the step stays at the resting maximum with nothing left.
  EXPECT_GT(world.lastStep().dt, 1e-3);
}

// The outcome counts bounces. A ball dropped from 2 m onto level terrain (Rn = 0.3) lands at
// sqrt(2 g 2) = 6.3 m/s, over STONE's 5 m/s: one bounce; it rises at 0.3 of that, 1.9 m/s, and
// lands again within 3 m at under 5 m/s, which starts rolling: no second bounce.
// A world of flat terrain (11 x 11 samples of 1 m at z = 0) holding a 0.25 m smooth ball whose
// bottom is `height` above the middle of it.
test::RockFallWorld ballOverFlatTerrain(WorldDef def, const RockFallDef& rockFall, double height) {
  def.terrain = flatTerrain(11, 11);
  test::RockFallWorld rock(def, rockFall);
  BodyDef b;
  b.shape = test::smoothBall(0.25, 100);
  b.position = Vec3(5, 5, 0.25 + height);
  rock.world.addBody(b);
  return rock;
}

TEST(Rockfall, TheOutcomeCountsBounces) {
  test::RockFallWorld rock =
      ballOverFlatTerrain({}, test::groundLaws(oneMaterial(0.3, 0.8, 0.3, 0.5)), 2.0);
  rock.world.advanceTo(3.0);
  EXPECT_EQ(rock.rockFall.outcomes()[0].bounces, 1);
}

// With sleeping on, a rock at rest falls asleep (0.5 s under 0.05 m/s) before the rest
// criterion's 1 s under 0.1 m/s has passed; asleep, it must still be reported stopped, so a run
// that stops on "all at rest" ends.
TEST(Rockfall, ASleepingRockCountsAsStopped) {
  WorldDef def;
  def.sleep = true;
  test::RockFallWorld rock = ballOverFlatTerrain(def, {}, 0.0);
  rock.world.advanceTo(2.0);
  ASSERT_TRUE(rock.world.isSleeping(0));
  EXPECT_EQ(rock.rockFall.outcomes()[0].state, RockState::kStopped);
  EXPECT_TRUE(rock.allSettled());
}

TEST(Rockfall, EdgePoliciesStopTheRunOrWallTheRockIn) {
  test::RockFallWorld stopped = rollTowardsEdge(TerrainEdge::kStop);
  stopped.world.advanceTo(5.0);
  const std::string& reason = stopped.rockFall.stopReason();
  EXPECT_NE(reason.find("body 0 left the terrain grid at t = 3.3"), std::string::npos) << reason;
  test::RockFallWorld walled = rollTowardsEdge(TerrainEdge::kWall);
  World& wall = walled.world;
  wall.advanceTo(5.0);
  EXPECT_EQ(walled.rockFall.outcomes()[0].state, RockState::kMoving);
  EXPECT_TRUE(wall.isActive(0));
  // Reflected at x = 20 after 3.33 s: heading west and back over the grid. The wall reverses
  // the velocity, not the spin, so friction then brings it to rolling with the angular
  // momentum about the contact, m r (-v0) + (2/5) m r v0: v = -(3/5) v0 / (7/5) = -1.29 m/s.
  EXPECT_NEAR(wall.velocity(0).x(), -3.0 * 3 / 7, 0.05);
  EXPECT_LT(wall.state(0).x.x(), 20.0);
  EXPECT_GT(wall.state(0).x.z(), 0.2);  // still on the surface, not fallen
}

TEST(Rockfall, ARockDroppedIntoANoDataHoleIsRemoved) {
  WorldDef def;
  def.terrain = flatTerrain(11, 11, {{5, 5}});  // the four cells around (5, 5) m have no data
  test::RockFallWorld rock(def, {});
  World& world = rock.world;
  BodyDef b;
  b.shape = test::smoothBall(0.25, 100);
  b.position = Vec3(5.2, 4.9, 3.0);
  world.addBody(b);
  world.advanceTo(2.0);
  const RockOutcome& r = rock.rockFall.outcomes()[0];
  EXPECT_EQ(r.state, RockState::kLeft);
  EXPECT_NE(r.message.find("body 0 entered a NODATA hole at t = 0.0"), std::string::npos)
      << r.message;
  EXPECT_EQ(world.measure().tunnelled, 0);
}

TEST(Rockfall, ABodyBelowTheSurfaceIsPushedOutOrStoppedNeverEjected) {
  for (double depth : {0.1, 1.0}) {  // centre 0.1 m below (partly) and 1 m below (wholly)
    WorldDef def;
    def.terrain = flatTerrain(11, 11);
    test::RockFallWorld rock(def, {});
    World& world = rock.world;
    BodyDef b;
    b.shape = test::smoothBall(0.25, 100);
    b.position = Vec3(5, 5, -depth);
    world.addBody(b);
    world.advanceTo(2.0);
    const RockOutcome& r = rock.rockFall.outcomes()[0];
    const std::vector<std::string>& messages = rock.rockFall.terrainMessages();
    ASSERT_FALSE(messages.empty());
    if (depth < 0.25) {
      EXPECT_NE(messages[0].find("body 0 was partly below the terrain surface at t = "),
                std::string::npos);
      // Out and resting on the surface (the leaf sphere's bottom at z = 0 within a step's fall),
      // never thrown: its speed stays below what gravity adds in a few steps.
      EXPECT_NEAR(world.state(0).x.z(), 0.25, 0.01);
      EXPECT_LT(world.velocity(0).norm(), 0.1);
      EXPECT_EQ(r.state, RockState::kStopped);
    } else {
      EXPECT_EQ(r.state, RockState::kBuried);
      EXPECT_NE(r.message.find("body 0 is wholly below the terrain surface at t = 0.0"),
                std::string::npos)
          << r.message;
      EXPECT_NEAR(world.state(0).x.z(), -depth, 0.01);
      EXPECT_FALSE(world.isActive(0));
    }
  }
}

}  // namespace vf

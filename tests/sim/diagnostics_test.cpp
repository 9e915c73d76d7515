// World::measure(), the oracle of every "never interpenetrates" test, against states placed by
// hand with a known answer: if measure() broke (say, always returned 0) the scenario tests
// that rely on it would still pass, so its readings are pinned here. Every expected value
// comes from the box geometry in the comments, not from running the code.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>

#include "sim/world.h"
#include "tests/support/test_world.h"

namespace vf {
namespace {

// test::bodyAt, static when asked.
BodyDef bodyAt(std::shared_ptr<const Shape> s, const Vec3& x, bool isStatic = false) {
  BodyDef b = test::bodyAt(std::move(s), x);
  b.isStatic = isStatic;
  return b;
}

// Boxes are centred on their centre of mass, so position = box centre. The distances below are
// differences of metre-sized coordinates: exact to ~1e-16, so 1e-12 is rounding only.
constexpr double kRounding = 1e-12;

TEST(Diagnostics, SeparatedBodiesReportNothing) {
  WorldDef def;
  def.groundHeight = 0.0;
  World world(def);
  auto s = test::boxShape(0.2, 0.2, 0.2, 800, 3);
  world.addBody(bodyAt(s, Vec3(0, 0, 0.1 + 1e-3)));
  world.addBody(bodyAt(s, Vec3(0.2 + 1e-3, 0, 0.1 + 1e-3)));
  const Diagnostics d = world.measure();
  EXPECT_EQ(d.maxPenetrationBodyBody, 0.0);
  EXPECT_EQ(d.maxPenetrationBodyGround, 0.0);
  EXPECT_EQ(d.tunnelled, 0);
}

TEST(Diagnostics, TwoBodiesOverlappingByAKnownDepth) {
  // A: 0.2 m cube at the origin (x in [-0.1, 0.1]). B: 0.2 x 0.1 x 0.1 box whose -x face sits at
  // x = 0.1 - 0.02, so B's four -x corners (y, z = +-0.05) lie 0.02 inside A's +x face and 0.05
  // from A's other faces: the deepest point of one mesh inside the other is 0.02 m. A's samples
  // inside B (the centroids of A's +x triangles) are at most 0.02 deep too.
  WorldDef def;
  def.gravity = Vec3::Zero();
  World world(def);
  const double depth = 0.02;
  world.addBody(bodyAt(test::boxShape(0.2, 0.2, 0.2, 800, 3), Vec3::Zero()));
  world.addBody(bodyAt(test::boxShape(0.2, 0.1, 0.1, 800, 3), Vec3(0.1 - depth + 0.1, 0, 0)));
  const Diagnostics d = world.measure();
  EXPECT_NEAR(d.maxPenetrationBodyBody, depth, kRounding);
  EXPECT_EQ(d.tunnelled, 0) << "neither centre is inside the other body";
}

TEST(Diagnostics, OverlapWithAStaticBodyCountsToo) {
  // Same geometry, A static: static-dynamic pairs are measured, static-static ones are not.
  WorldDef def;
  World world(def);
  world.addBody(bodyAt(test::boxShape(0.2, 0.2, 0.2, 800, 3), Vec3::Zero(), true));
  world.addBody(bodyAt(test::boxShape(0.2, 0.1, 0.1, 800, 3), Vec3(0.17, 0, 0)));
  EXPECT_NEAR(world.measure().maxPenetrationBodyBody, 0.03, kRounding);
}

TEST(Diagnostics, BodyBelowTheFloor) {
  // 0.2 m cube with its centre at z = 0.07 on the floor z = 0: its bottom corners are 0.03 m
  // below the floor; its centre is above it, so it has not tunnelled.
  WorldDef def;
  def.groundHeight = 0.0;
  World world(def);
  auto s = test::boxShape(0.2, 0.2, 0.2, 800, 3);
  world.addBody(bodyAt(s, Vec3(0, 0, 0.07)));
  Diagnostics d = world.measure();
  EXPECT_NEAR(d.maxPenetrationBodyGround, 0.03, kRounding);
  EXPECT_EQ(d.tunnelled, 0);

  // Centre 0.01 m below the floor: 0.11 m deep, and tunnelled through the ground.
  World sunk(def);
  sunk.addBody(bodyAt(s, Vec3(3, 0, -0.01)));
  d = sunk.measure();
  EXPECT_NEAR(d.maxPenetrationBodyGround, 0.11, kRounding);
  EXPECT_EQ(d.tunnelled, 1);
}

TEST(Diagnostics, BodyBelowTheTerrain) {
  // A flat grid at z = 0.5 over [-2, 2]^2: the cube's centre at z = 0.5 + 0.06 puts its bottom
  // 0.04 m under the surface.
  WorldDef def;
  def.terrain = std::make_shared<Heightfield>(test::flatHeightfield(5, 5, 1, 0.5, -2, -2));
  test::RockFallWorld rock(def, {});  // with the rock monitor, as a scene on terrain has
  World& world = rock.world;
  world.addBody(bodyAt(test::boxShape(0.2, 0.2, 0.2, 800, 3), Vec3(0.3, -0.4, 0.56)));
  Diagnostics d = world.measure();
  EXPECT_NEAR(d.maxPenetrationBodyGround, 0.04, kRounding);
  EXPECT_EQ(d.tunnelled, 0);

  // Centre 0.05 m under the surface. A body released there would be pushed out at once (the
  // rock monitor), so the sunk state is handed to measure() directly.
  std::vector<BodyState> sunk{world.state(0)};
  sunk[0].x.z() = 0.45;
  d = world.measure(sunk);
  EXPECT_NEAR(d.maxPenetrationBodyGround, 0.15, kRounding);
  EXPECT_EQ(d.tunnelled, 1);
}

TEST(Diagnostics, ABodyThatTunnelledIntoAnother) {
  // A 0.05 m cube whose centre lies inside a 0.4 m cube (both dynamic): the small one has
  // tunnelled (its centre is inside the other solid); the big one's centre is not inside the
  // small one. The small cube lies wholly inside; its deepest samples, the corners of its -x face
  // (x = 0.075, |y|, |z| = 0.025), are 0.2 - 0.075 = 0.125 m from the big cube's nearest face.
  WorldDef def;
  def.gravity = Vec3::Zero();
  World world(def);
  world.addBody(bodyAt(test::boxShape(0.4, 0.4, 0.4, 800, 3), Vec3::Zero()));
  world.addBody(bodyAt(test::boxShape(0.05, 0.05, 0.05, 800, 3), Vec3(0.1, 0, 0)));
  const Diagnostics d = world.measure();
  EXPECT_EQ(d.tunnelled, 1);
  EXPECT_NEAR(d.maxPenetrationBodyBody, 0.125, kRounding);
}

TEST(Diagnostics, EnergiesByHand) {
  // m = 800 * 0.2^3 = 6.4 kg at z = 2 moving at 3 m/s without spin: KE = m 9 / 2, PE = m g z.
  WorldDef def;
  World world(def);
  BodyDef b = bodyAt(test::boxShape(0.2, 0.2, 0.2, 800, 2), Vec3(0, 0, 2));
  b.velocity = Vec3(3, 0, 0);
  world.addBody(b);
  const Diagnostics d = world.measure();
  const double m = 800 * 0.008;
  EXPECT_NEAR(d.kineticEnergy, 0.5 * m * 9, 1e-9);
  EXPECT_NEAR(d.potentialEnergy, m * 9.81 * 2, 1e-9);
}

// A 0.1 m cube wholly inside a 1 m cube, centres together, surfaces 0.45 m apart (no leaf
// spheres of the two touch): every sample of the small cube lies on its faces, at most 0.05 m
// from the centre along some axis, so the deepest is 0.5 - 0.05 = 0.45 m inside the big one. A
// shortcut that judged pairs by touching surfaces alone would read 0 here.
TEST(Diagnostics, ABodyWhollyInsideAnotherWithoutTouchingSurfaces) {
  World world(WorldDef{});
  auto big = test::boxShape(1.0, 1.0, 1.0, 800, 3);
  auto small = test::boxShape(0.1, 0.1, 0.1, 800, 3);
  world.addBody(bodyAt(big, Vec3(0, 0, 5)));
  world.addBody(bodyAt(small, Vec3(0, 0, 5)));
  EXPECT_NEAR(world.measure().maxPenetrationBodyBody, 0.45, kRounding);
}

}  // namespace
}  // namespace vf

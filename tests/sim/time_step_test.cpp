// The step-size rule of eqs. 17-20.
#include "sim/solve/time_step.h"

#include <gtest/gtest.h>

#include <cmath>

#include "sim/shape/heightfield.h"
#include "tests/support/test_world.h"

namespace vf {
namespace {

// The paper's eq. 20 for one kind of body, written here as the oracle (production code solves
// the gravity-corrected form in stableStep): dt = l / (2^(Lv+1) (v + (l/2) w)).
double eq20Step(double diameter, int level, double speed, double angularSpeed) {
  return diameter / (std::ldexp(1.0, level + 1) * (speed + 0.5 * diameter * angularSpeed));
}

struct Bodies {
  std::vector<BodyInfo> bodies;
  std::vector<BodyState> states;
  void add(std::shared_ptr<const Shape> s, const Vec3& v, const Vec3& w) {
    BodyInfo b;
    b.shape = s;
    b.invMass = 1 / s->mass;
    b.inertiaBodyInv = s->inertiaBodyInv;
    bodies.push_back(b);
    BodyState y;
    y.P = s->mass * v;
    y.L = s->inertiaBody * w;
    states.push_back(y);
  }
};

TEST(TimeStep, OneBodyWithoutGravityIsEq20ByHand) {
  // Box 0.3 x 0.2 x 0.1: l = its diagonal sqrt(0.14) m (eq. 18's l: twice the largest vertex
  // distance from the centre of mass); Lv 4: r = l / 2^5 (eq. 19). At v = 2 m/s and w = 4 rad/s
  // about z: v_max = 2 + (l/2) 4 (eq. 18); with g = 0, dt = r / v_max (eq. 20).
  auto s = test::boxShape(0.3, 0.2, 0.1, 800, 4);
  const double l = std::sqrt(0.14);
  ASSERT_NEAR(s->diameter, l, 1e-15);
  Bodies w;
  w.add(s, Vec3(2, 0, 0), Vec3(0, 0, 4));
  EXPECT_NEAR(stableStep(w.bodies, w.states, Vec3::Zero(), 1.0), (l / 32) / (2 + 0.5 * l * 4),
              1e-15);
}

TEST(TimeStep, ZeroGravityIsEq20WithMaximaOverBodies) {
  auto s = test::boxShape(0.3, 0.2, 0.1, 800, 4);
  Bodies w;
  w.add(s, Vec3(1, 0, 0), Vec3(0, 0, 2));
  w.add(s, Vec3(0, 3, 0), Vec3::Zero());
  // v_g,max = 3, w_max = 2 (eq. 18 takes the maxima separately).
  const double expected = eq20Step(s->diameter, 4, 3.0, 2.0);
  EXPECT_DOUBLE_EQ(stableStep(w.bodies, w.states, Vec3::Zero(), 1.0), expected);
}

TEST(TimeStep, GravityIncrementKeepsEq17OverTheWholeStep) {
  auto s = test::boxShape(0.3, 0.2, 0.1, 800, 4);
  Bodies w;
  w.add(s, Vec3(2, 0, 0), Vec3::Zero());
  const double g = 9.81;
  const double dt = stableStep(w.bodies, w.states, Vec3(0, 0, -g), 1.0);
  const double r = std::ldexp(s->diameter, -5);
  // Eq. 17 with the speed at the end of the step: dt (v + g dt) = r, to rounding.
  EXPECT_NEAR(dt * (2.0 + g * dt), r, 1e-12);
  EXPECT_LT(dt, eq20Step(s->diameter, 4, 2.0, 0.0));
}

TEST(TimeStep, RestingWorldTakesTheCap) {
  auto s = test::boxShape(0.3, 0.2, 0.1, 800, 4);
  Bodies w;
  w.add(s, Vec3::Zero(), Vec3::Zero());
  w.bodies[0].isStatic = true;  // nothing moves
  EXPECT_EQ(stableStep(w.bodies, w.states, Vec3(0, 0, -9.81), 0.02), 0.02);
}

// The clearance rule (clearanceStep, an extension). Independent oracles: eq. 17 per body
// (the root written out below), the time two bodies need to close their gap at their speeds, and
// the time a body falls to the floor; every case is built so that one of them decides. Gaps are
// shortened by the rounding slack (1e-9 m per body plus 1e-9 of its distance from the origin,
// roundingSlack: under 3e-8 m here), hence 1e-8 s where a gap decides.
double eq17Root(double speed, double g, double move) {  // dt with dt (speed + g dt) = move
  return g > 0 ? 2 * move / (speed + std::sqrt(speed * speed + 4 * g * move)) : move / speed;
}

TEST(TimeStep, ClearanceRuleGivesABodyOnTheFloorItsOwnEq17Step) {
  auto s = test::boxShape(0.3, 0.2, 0.1, 800, 4);
  Bodies w;
  w.add(s, Vec3(2, 0, 0), Vec3(0, 0, 3));
  w.states[0].x = Vec3(0, 0, 0.04);  // its bounding sphere reaches below the floor z = 0
  const double g = 9.81, r = std::ldexp(s->diameter, -5);
  const double speed = 2 + 0.5 * s->diameter * 3;
  EXPECT_NEAR(clearanceStep(w.bodies, w.states, Vec3(0, 0, -g), 1.0, 0.0, nullptr),
              eq17Root(speed, g, r), 1e-15);
  // One body: eq. 17 per body is eq. 20.
  EXPECT_NEAR(clearanceStep(w.bodies, w.states, Vec3(0, 0, -g), 1.0, 0.0, nullptr),
              stableStep(w.bodies, w.states, Vec3(0, 0, -g), 1.0), 1e-15);
}

TEST(TimeStep, ClearanceRuleLetsABodyHighAboveTheFloorFallToIt) {
  auto s = test::boxShape(0.3, 0.2, 0.1, 800, 4);
  Bodies w;
  w.add(s, Vec3(0, 0, -5), Vec3::Zero());
  const double g = 9.81, R = s->tree->boundingRadius, h = 2.0;
  w.states[0].x = Vec3(0, 0, R + h);  // its bounding sphere h above the floor
  const double maxStep = 1.0;         // budget (5 + g) m: the gap h decides
  const double dt = clearanceStep(w.bodies, w.states, Vec3(0, 0, -g), maxStep, 0.0, nullptr);
  EXPECT_NEAR(dt, eq17Root(5.0, g, h), 1e-8);
  EXPECT_GT(dt, 100 * stableStep(w.bodies, w.states, Vec3(0, 0, -g), maxStep));
  // With a budget under the gap (1/60 s at 5 m/s: 0.086 m < 2 m) the cap decides.
  EXPECT_EQ(clearanceStep(w.bodies, w.states, Vec3(0, 0, -g), 1.0 / 60, 0.0, nullptr), 1.0 / 60);
}

TEST(TimeStep, ClearanceRuleStopsTwoBodiesWhereTheirGapWouldClose) {
  auto s = test::boxShape(0.3, 0.2, 0.1, 800, 4);
  Bodies w;
  w.add(s, Vec3(3, 0, 0), Vec3::Zero());
  w.add(s, Vec3(-1, 0, 0), Vec3::Zero());
  const double R = s->tree->boundingRadius, gap = 1.0;
  w.states[1].x = Vec3(2 * R + gap, 0, 0);
  // No gravity, no floor: they close the gap at 4 m/s, each moving its share (3/4 and 1/4 of
  // it), so both reach it at gap / 4 s; bounding spheres touch there at the earliest.
  EXPECT_NEAR(clearanceStep(w.bodies, w.states, Vec3::Zero(), 1.0, std::nullopt, nullptr), gap / 4,
              1e-8);
  // A body at rest leaves the whole gap to the moving one.
  w.states[1].P = Vec3::Zero();
  EXPECT_NEAR(clearanceStep(w.bodies, w.states, Vec3::Zero(), 1.0, std::nullopt, nullptr), gap / 3,
              1e-8);
  // Bounding spheres overlapping: eq. 17 for both, per body (the faster one decides).
  w.states[1].x = Vec3(2 * R - 0.01, 0, 0);
  EXPECT_NEAR(clearanceStep(w.bodies, w.states, Vec3::Zero(), 1.0, std::nullopt, nullptr),
              std::ldexp(s->diameter, -5) / 3, 1e-15);
}

TEST(TimeStep, ClearanceRuleKeepsBodiesClearOfTheTerrain) {
  // A planar 1 m grid rising 0.5 m per m along x; a body above it, falling. Its bounding sphere
  // must stay above Heightfield::surfaceBoundNear over the square it could reach, so the step
  // can be no longer than the fall to that bound, and at least eq. 17.
  Heightfield hf = test::flatHeightfield(41, 41, 1.0, 0.0);
  for (int j = 0; j < hf.ny; ++j)
    for (int i = 0; i < hf.nx; ++i) hf.z[static_cast<std::size_t>(j) * hf.nx + i] = 0.5 * i;
  hf.zMax = 20;
  ASSERT_NEAR(hf.heightAt(20, 20), 10.0, 1e-12);
  auto s = test::boxShape(0.3, 0.2, 0.1, 800, 4);
  Bodies w;
  w.add(s, Vec3(0, 0, -3), Vec3::Zero());
  const double g = 9.81, R = s->tree->boundingRadius;
  w.states[0].x = Vec3(20, 20, 10 + R + 1.5);  // the surface under it is 10 m high
  const double maxStep = 0.25;                 // budget (3 + g maxStep) maxStep = 1.36 m
  const double dt = clearanceStep(w.bodies, w.states, Vec3(0, 0, -g), maxStep, std::nullopt, &hf);
  const double budget = (3 + g * maxStep) * maxStep;
  const double bound = hf.surfaceBoundNear(20, 20, R + budget);
  const double clearance = w.states[0].x.z() - R - bound;
  ASSERT_GT(clearance, 0.0);
  ASSERT_LT(clearance, 1.5);  // the slope under the reachable square rises above the point's 10 m
  EXPECT_NEAR(dt, eq17Root(3.0, g, clearance), 1e-8);
  EXPECT_GE(dt, stableStep(w.bodies, w.states, Vec3(0, 0, -g), maxStep));
}

// Never shorter than eq. 20: 200 seeded random worlds of 6 bodies over a floor (positions,
// velocities and spins drawn at random, some bodies asleep or static).
TEST(TimeStep, ClearanceRuleIsNeverShorterThanEq20) {
  auto s = test::boxShape(0.3, 0.2, 0.1, 800, 3);
  std::uint64_t seed = 12345;
  auto uniform = [&seed](double lo, double hi) {  // splitmix64
    seed += 0x9e3779b97f4a7c15ULL;
    std::uint64_t z = seed;
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    z ^= z >> 31;
    return lo + (hi - lo) * static_cast<double>(z >> 11) * 0x1.0p-53;
  };
  for (int world = 0; world < 200; ++world) {
    Bodies w;
    for (int i = 0; i < 6; ++i) {
      w.add(s, Vec3(uniform(-5, 5), uniform(-5, 5), uniform(-5, 5)),
            Vec3(uniform(-9, 9), uniform(-9, 9), uniform(-9, 9)));
      w.states[i].x = Vec3(uniform(-1, 1), uniform(-1, 1), uniform(0, 2));
      w.bodies[i].sleeping = uniform(0, 1) < 0.15;
      w.bodies[i].isStatic = uniform(0, 1) < 0.1;
    }
    const Vec3 gravity(0, 0, -9.81);
    EXPECT_GE(clearanceStep(w.bodies, w.states, gravity, 1.0 / 60, 0.0, nullptr),
              stableStep(w.bodies, w.states, gravity, 1.0 / 60))
        << "world " << world;
  }
}

}  // namespace
}  // namespace vf

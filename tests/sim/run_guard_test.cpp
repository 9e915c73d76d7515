// The run guard (sim/run_guard.h): runs that would take too many steps or start too fast are
// refused before any step; non-finite states, speeds over the bound and energy gains over the
// margin stop a run with the body, the time and the quantity. Expected values are by hand.
#include "sim/run_guard.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "sim/core/error.h"
#include "sim/run_length.h"
#include "sim/world.h"
#include "tests/support/test_world.h"

namespace vf {
namespace {

// test::bodyAt with an initial velocity v (m/s).
BodyDef bodyAt(std::shared_ptr<const Shape> s, const Vec3& x, const Vec3& v = Vec3::Zero()) {
  BodyDef b = test::bodyAt(std::move(s), x);
  b.velocity = v;
  return b;
}

std::string refusal(const World& world, double duration, const RunLimits& limits) {
  const std::vector<std::string> where(world.bodyCount(), "scene.toml:7:1");
  try {
    checkRunLength(world, duration, limits, where);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(RunGuard, ABodyStartingAtAbsurdSpeedIsRefusedBeforeTheRun) {
  World world{WorldDef{}};
  auto s = test::boxShape(0.2, 0.2, 0.2, 800, 2);
  world.addBody(bodyAt(s, Vec3(0, 0, 1)));
  world.addBody(bodyAt(s, Vec3(2, 0, 1), Vec3(1e30, 0, 0)));
  const std::string msg = refusal(world, 2.0, RunLimits{});
  EXPECT_NE(msg.find("scene.toml:7:1: body 1 (shape 'box')"), std::string::npos) << msg;
  EXPECT_NE(msg.find("1e+30 m/s"), std::string::npos) << msg;
  EXPECT_NE(msg.find("limit of 1000 m/s"), std::string::npos) << msg;
  EXPECT_NE(msg.find("--max-speed"), std::string::npos) << msg;
  // Raising the bound lets the speed pass (the step count is then the floor's 2e6 steps).
  RunLimits raised;
  raised.maxSpeed = 2e30;
  EXPECT_EQ(refusal(world, 2.0, raised), "");
}

TEST(RunGuard, AFixedStepNeedingTooManyStepsIsRefused) {
  WorldDef def;
  def.step = StepRule::fixed(1e-7);  // 2 s / 1e-7 s = 2e7 steps > 1e7
  World world(def);
  world.addBody(bodyAt(test::boxShape(0.2, 0.2, 0.2, 800, 2), Vec3(0, 0, 1)));
  const std::string msg = refusal(world, 2.0, RunLimits{});
  EXPECT_NE(msg.find("needs about 2e+07 steps over 2 s, over the limit of 10000000"),
            std::string::npos)
      << msg;
  EXPECT_NE(msg.find("--max-steps"), std::string::npos) << msg;
  EXPECT_EQ(refusal(world, 0.5, RunLimits{}), "") << "5e6 steps are within the limit";
  RunLimits raised;
  raised.maxSteps = 30'000'000;
  EXPECT_EQ(refusal(world, 2.0, raised), "");
}

TEST(RunGuard, StepEstimateMatchesAFreeFallRun) {
  // A 0.2 m cube at Lv 2 thrown down at 5 m/s with no ground: its speed is v + g t, and the
  // estimate T (v + g T / 2 + g maxStep) / r bounds the integral of 1 / dt for the rule
  // dt (v + g t + g dt) = r. The run takes equal steps no longer than the rule that land on T
  // exactly, a few more than the integral (232 against 232.6 when the steps had to land on T), so
  // 5 % is ample.
  WorldDef def;
  World world(def);
  auto s = test::boxShape(0.2, 0.2, 0.2, 800, 2);
  world.addBody(bodyAt(s, Vec3(0, 0, 1), Vec3(0, 0, -5)));
  const double l = std::sqrt(3.0) * 0.2, r = l / 8, T = 1.0;
  const double estimate = estimatedSteps(world, 0, T);
  EXPECT_NEAR(estimate, T * (5 + 0.5 * 9.81 * T + 9.81 / 60) / r, 1e-9);
  world.advanceTo(T);
  const double steps = static_cast<double>(world.totals().steps);
  EXPECT_NEAR(steps, estimate, 0.05 * estimate);
  // A step count just below the estimate is refused, one just above is not.
  World fresh(def);
  fresh.addBody(bodyAt(s, Vec3(0, 0, 1), Vec3(0, 0, -5)));
  RunLimits tight;
  tight.maxSteps = static_cast<std::uint64_t>(estimate) - 1;
  EXPECT_NE(refusal(fresh, T, tight).find("level 2 starting at 5 m/s"), std::string::npos);
  tight.maxSteps = static_cast<std::uint64_t>(estimate) + 1;
  EXPECT_EQ(refusal(fresh, T, tight), "");
}

TEST(RunGuard, AFloorBoundsTheStepEstimateByEnergy) {
  // The same cube 1 m above a floor plane: its kinetic energy can never exceed
  // K = K0 + m g (1 + l/2), so |v| <= sqrt(2K/m) and |w| <= sqrt(2K/I) with I = m a^2/6 for a
  // cube: the estimate is T (sqrt(2K/m) + (l/2) sqrt(2K/I) + g/60) / r, linear in T. Over 60 s
  // the free-fall bound (quadratic in T) would be 25 times larger.
  WorldDef def;
  def.groundHeight = 0.0;
  World world(def);
  const double a = 0.2, l = std::sqrt(3.0) * a, r = l / 8, T = 60.0, g = 9.81;
  auto s = test::boxShape(a, a, a, 800, 2);
  world.addBody(bodyAt(s, Vec3(0, 0, 1), Vec3(0, 0, -5)));
  const double kPerMass = 0.5 * 25 + g * (1 + 0.5 * l);
  const double expected =
      T * (std::sqrt(2 * kPerMass) + 0.5 * l * std::sqrt(2 * kPerMass * 6 / (a * a)) + g / 60) / r;
  EXPECT_NEAR(estimatedSteps(world, 0, T), expected, 1e-9 * expected);
  // The run itself stays under the bound (it lands, bounces and rests).
  world.advanceTo(T);
  EXPECT_LT(static_cast<double>(world.totals().steps), expected);
  // Without the floor the body falls for the whole minute: the free-fall estimate stands.
  World noFloor{WorldDef{}};
  noFloor.addBody(bodyAt(s, Vec3(0, 0, 1), Vec3(0, 0, -5)));
  EXPECT_NEAR(estimatedSteps(noFloor, 0, T), T * (5 + 0.5 * g * T + g / 60) / r, 1e-6);
}

TEST(RunGuard, ABodyFasterThanTheBoundStopsTheRunWithBodyAndTime) {
  // Free fall from rest reaches 10 m/s at t = 10 / 9.81 s; with the bound at 10 m/s the run
  // stops in the step during which the speed crossed it (the check sees the momentum after
  // gravity's increment, before the move).
  WorldDef def;
  def.limits.maxSpeed = 10;
  World world(def);
  auto s = test::boxShape(0.2, 0.2, 0.2, 800, 2);
  world.addBody(bodyAt(s, Vec3(5, 0, 100)));
  world.addBody(bodyAt(s, Vec3(0, 0, 100), Vec3(0, 0, -1)));  // 1 m/s ahead: over first
  try {
    world.advanceTo(2.0);
    FAIL() << "the run should have stopped";
  } catch (const RunawayError& e) {
    const Runaway& r = e.runaway();
    EXPECT_EQ(r.body, 1);
    EXPECT_EQ(r.quantity, "speed");
    EXPECT_GT(r.value, 10.0);
    EXPECT_LT(r.value, 10.0 + 9.81 * world.totals().dtMax);
    const double crossing = 9 / 9.81;
    EXPECT_LE(r.time, crossing);
    EXPECT_GT(r.time, crossing - world.totals().dtMax);
    EXPECT_NE(std::string(e.what()).find("body 1 (shape 'box') at t = 0.91"), std::string::npos)
        << e.what();
  }
  ASSERT_TRUE(world.runaway().has_value());
  const double stoppedAt = world.time();
  EXPECT_THROW(world.step(0.1), RunawayError);  // a stopped world stays stopped
  EXPECT_EQ(world.time(), stoppedAt);
}

TEST(RunGuard, ANonFiniteStateStopsTheRun) {
  World world{WorldDef{}};
  auto s = test::boxShape(0.2, 0.2, 0.2, 800, 2);
  world.addBody(bodyAt(s, Vec3(0, 0, 1)));
  world.addBody(bodyAt(s, Vec3(3, 0, 1), Vec3(std::numeric_limits<double>::quiet_NaN(), 0, 0)));
  try {
    world.advanceTo(0.5);
    FAIL() << "the run should have stopped";
  } catch (const RunawayError& e) {
    EXPECT_EQ(e.runaway().body, 1);
    EXPECT_EQ(e.runaway().quantity, "non-finite state");
    EXPECT_EQ(e.runaway().time, 0.0);
  }
}

// One cube (m = 6.4 kg, l = 0.2 sqrt(3) m) checked directly, with g = 10 m/s^2 and dt = 0 so the
// potential energy is -m g.x of the state as given.
struct OneCube {
  std::vector<BodyInfo> bodies{1};
  std::vector<BodyState> states{1};
  Vec3 g{0, 0, -10};
  double m = 6.4, l = 0.2 * std::sqrt(3.0);
  OneCube() {
    auto s = test::boxShape(0.2, 0.2, 0.2, 800, 2);
    bodies[0].shape = s;
    bodies[0].invMass = 1 / s->mass;
    bodies[0].inertiaBodyInv = s->inertiaBodyInv;
    states[0].x = Vec3(0, 0, 1);
  }
  // Sets the speed (along x) so that the kinetic energy is `joules`.
  void kinetic(double joules) { states[0].P = Vec3(std::sqrt(2 * m * joules), 0, 0); }
};

TEST(RunGuard, EnergyGainOverTheMarginStopsTheRun) {
  // Released at rest: E_release = -m g.x, scale S = m |g| l. The margin 0.5 allows a gain of
  // 0.5 S: 0.4 S passes, 0.6 S stops the run and names the energy.
  OneCube c;
  ASSERT_NEAR(c.bodies[0].shape->mass, c.m, 1e-12);
  ASSERT_NEAR(c.bodies[0].shape->diameter, c.l, 1e-15);
  const double S = c.m * 10 * c.l;
  RunGuard guard;
  RunLimits limits;
  EXPECT_FALSE(guard.check(c.bodies, c.states, c.g, 0.0, 0.0, limits));
  c.kinetic(0.4 * S);
  EXPECT_FALSE(guard.check(c.bodies, c.states, c.g, 0.1, 0.0, limits));
  EXPECT_NEAR(guard.peakGainRatio(), 0.4, 1e-9);
  c.kinetic(0.6 * S);
  const auto r = guard.check(c.bodies, c.states, c.g, 0.2, 0.0, limits);
  ASSERT_TRUE(r);
  EXPECT_EQ(r->quantity, "energy");
  EXPECT_EQ(r->body, 0);
  EXPECT_EQ(r->time, 0.2);
  EXPECT_NEAR(r->value, 0.6 * S, 1e-9 * S);
  EXPECT_NEAR(r->limit, 0.5 * S, 1e-9 * S);
}

TEST(RunGuard, FallingTurnsPotentialIntoKineticEnergyWithoutAGain) {
  // Dropped by h = 20 m with the kinetic energy m g h that falling gives: no gain at all, and
  // the released potential energy m g h widens the allowance to 0.5 (S + m g h).
  OneCube c;
  RunGuard guard;
  RunLimits limits;
  EXPECT_FALSE(guard.check(c.bodies, c.states, c.g, 0.0, 0.0, limits));
  c.states[0].x.z() -= 20;
  c.kinetic(c.m * 10 * 20);
  EXPECT_FALSE(guard.check(c.bodies, c.states, c.g, 2.0, 0.0, limits));
  EXPECT_NEAR(guard.peakGainRatio(), 0.0, 1e-12);
  // A gain of 0.4 (S + m g h) still passes, 0.6 (S + m g h) does not.
  const double wide = c.m * 10 * c.l + c.m * 10 * 20;
  c.kinetic(c.m * 10 * 20 + 0.4 * wide);
  EXPECT_FALSE(guard.check(c.bodies, c.states, c.g, 2.1, 0.0, limits));
  c.kinetic(c.m * 10 * 20 + 0.6 * wide);
  EXPECT_TRUE(guard.check(c.bodies, c.states, c.g, 2.2, 0.0, limits));
}

}  // namespace
}  // namespace vf

// The step-size rule of eqs. 17-20.
#include "sim/solve/time_step.h"

#include <gtest/gtest.h>

#include <cmath>

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

}  // namespace
}  // namespace vf

// A torque-free platy rock spun about its middle principal axis: the motion rock-fall codes
// must keep (Leine et al. 2021, Multibody Syst. Dyn. 52:431-455, section 4). The spin about the
// middle axis is unstable: the rock flips over and back periodically while its angular momentum
// L (world frame) and kinetic energy stay constant.
//
// Oracle: Euler's equations in the body frame, I w' = (I w) x w, integrated independently of
// World by classical Runge-Kutta at a step 1/200 of the simulation's (its error, O(h^4), is
// negligible against the simulation's O(dt^2)). The checks are convergence orders, derived
// from the method and not tuned: the midpoint rotation update is second order, so halving the
// step must divide its energy error by about 4; the paper's explicit Euler is first order.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "sim/solve/rotation_update.h"
#include "sim/world.h"
#include "tests/support/test_world.h"

namespace vf {
namespace {

constexpr double kDuration = 8.0;  // s: covers two flips of the middle axis at these rates
constexpr double kSample = 0.05;   // s between comparisons with the reference

struct SpinRun {
  double energyDrift = 0;  // |E(T) - E(0)| / E(0)
  double omegaError = 0;   // max over samples of |w_body - w_reference| / |w_0|
  int flips = 0;           // sign changes of the body-frame spin about the middle axis
  bool momentumKept = false;
};

Vec3 eulerRate(const Mat3& inertia, const Mat3& inverse, const Vec3& w) {
  return inverse * (inertia * w).cross(w);
}

// One classical Runge-Kutta step of Euler's equations.
Vec3 rk4(const Mat3& inertia, const Mat3& inverse, const Vec3& w, double h) {
  const Vec3 k1 = eulerRate(inertia, inverse, w);
  const Vec3 k2 = eulerRate(inertia, inverse, w + 0.5 * h * k1);
  const Vec3 k3 = eulerRate(inertia, inverse, w + 0.5 * h * k2);
  const Vec3 k4 = eulerRate(inertia, inverse, w + h * k3);
  return w + (h / 6) * (k1 + 2 * k2 + 2 * k3 + k4);
}

SpinRun spin(RotationUpdate rotation, double dt) {
  WorldDef def;
  def.gravity = Vec3::Zero();
  def.step = StepRule::fixed(dt);
  def.rotation = rotation;
  World world(def);
  BodyDef b;
  // A platy block, 0.9 x 0.6 x 0.3 m of rock (2,700 kg/m^3): three distinct principal moments,
  // the middle one about y. Spun at 6 rad/s about y with a small component about the others.
  b.shape = test::boxShape(0.9, 0.6, 0.3, 2700, 2);
  b.angularVelocity = Vec3(0.02, 6.0, 0.02);
  world.addBody(b);

  const Mat3 inertia = b.shape->inertiaBody;
  const Mat3 inverse = inertia.inverse();
  const Mat3 R0 = world.state(0).q.toRotationMatrix();
  Vec3 reference = R0.transpose() * world.angularVelocity(0);
  const double w0 = reference.norm();
  const Vec3 L0 = world.state(0).L;
  const double E0 = world.measure().kineticEnergy;

  SpinRun run;
  double lastMiddle = reference.y();
  const int samples = static_cast<int>(std::lround(kDuration / kSample));
  const int substeps = static_cast<int>(std::lround(200 * kSample / dt));
  for (int i = 1; i <= samples; ++i) {
    for (int k = 0; k < substeps; ++k)
      reference = rk4(inertia, inverse, reference, kSample / substeps);
    world.advanceTo(i * kSample);
    const Mat3 R = world.state(0).q.toRotationMatrix();
    const Vec3 w = R.transpose() * world.angularVelocity(0);
    run.omegaError = std::max(run.omegaError, (w - reference).norm() / w0);
    if ((w.y() > 0) != (lastMiddle > 0)) ++run.flips;
    lastMiddle = w.y();
  }
  run.energyDrift = std::abs(world.measure().kineticEnergy - E0) / E0;
  run.momentumKept = world.state(0).L == L0;
  return run;
}

TEST(PlatySpin, MidpointUpdateKeepsTheMiddleAxisFlipsAndIsSecondOrder) {
  // 2 ms is the step of RAMMS (Leine et al. 2021; Lu et al. 2019).
  const SpinRun a = spin(RotationUpdate::kMidpoint, 2e-3);
  const SpinRun b = spin(RotationUpdate::kMidpoint, 1e-3);
  std::printf("midpoint: energy drift %.2e (2 ms), %.2e (1 ms); spin error %.2e, %.2e; flips %d\n",
              a.energyDrift, b.energyDrift, a.omegaError, b.omegaError, a.flips);
  EXPECT_TRUE(a.momentumKept);  // no torque acts: L is never touched
  EXPECT_TRUE(b.momentumKept);
  // The reference flips; so must the rock (a damped update would settle the spin instead).
  EXPECT_GE(a.flips, 2);
  EXPECT_EQ(a.flips, b.flips);
  // Second order: halving the step divides the energy error by 4 (3 to 5 allows for the next
  // order) and the spin's error by at least that (it falls faster here, by about 8 per halving
  // from 2 ms down to 0.25 ms: the update is at least second order, which is all it promises).
  EXPECT_GT(a.energyDrift / b.energyDrift, 3.0);
  EXPECT_LT(a.energyDrift / b.energyDrift, 5.0);
  EXPECT_GT(a.omegaError / b.omegaError, 3.0);
}

TEST(PlatySpin, ExplicitEulerIsFirstOrderAndGainsEnergy) {
  // The oracle must tell the orders apart: the paper's update halves its errors, no more.
  const SpinRun a = spin(RotationUpdate::kExplicitEuler, 2e-3);
  const SpinRun b = spin(RotationUpdate::kExplicitEuler, 1e-3);
  std::printf("euler: energy drift %.2e (2 ms), %.2e (1 ms); spin error %.2e, %.2e\n",
              a.energyDrift, b.energyDrift, a.omegaError, b.omegaError);
  EXPECT_GT(a.energyDrift / b.energyDrift, 1.5);
  EXPECT_LT(a.energyDrift / b.energyDrift, 2.5);
  const SpinRun m = spin(RotationUpdate::kMidpoint, 2e-3);
  EXPECT_GT(a.energyDrift, 10 * m.energyDrift);
}

}  // namespace
}  // namespace vf

// Before a run (checkRunLength): the step rule is global (the fastest body sets everyone's
// step), so one fast, spinning or tiny body can make a run take billions of steps. For each body
// the steps are estimated as if it fell freely for the whole run: with dt = r / (v + g t + g dt)
// (eq. 20 with gravity's increment, r = l / 2^(Lv+1)), the count is the integral of 1 / dt,
// at most T (v + g T / 2 + g maxStep) / r, bounded by T / maxStep below and T / minStep above
// (the world's step bounds), or T / the fixed step. A body that lands moves slower than
// in free fall, so this is an upper bound for rock fall; a run whose estimate exceeds
// RunLimits::maxSteps is refused before any step, naming the body and what to change. A body that
// starts faster than RunLimits::maxSpeed is refused too. During the run, RunGuard
// (run_guard.cpp) takes over.
#include "sim/run_length.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <optional>

#include "sim/core/error.h"
#include "sim/shape/heightfield.h"
#include "sim/shape/shape.h"

namespace vf {

double estimatedSteps(const World& world, int id, double duration) {
  const WorldDef& d = world.def();
  if (d.step.isFixed()) return std::ceil(duration / d.step.seconds);
  const double atRest = duration / d.maxStep;
  if (world.isStatic(id)) return atRest;
  const Shape& s = world.shape(id);
  const double r = s.stepRadius();  // eq. 19
  const double v = world.velocity(id).norm() + 0.5 * s.diameter * world.angularVelocity(id).norm();
  // 1 / dt = (v(t) + g dt) / r (eq. 17 with the speed at the end of the step, dt <= maxStep).
  const double g = d.gravity.norm();
  double estimate = duration * (v + 0.5 * g * duration + g * d.maxStep) / r;
  // With a floor plane or terrain under gravity along -z the body cannot fall forever: contacts
  // only remove energy, so its kinetic energy stays below K = K0 + m g (z0 - floor + l/2), where
  // the floor is the lowest ground (the centre of mass cannot go lower than half the body's size
  // below it). Then |v| <= sqrt(2K/m) and |w| <= sqrt(2K/I_min), and 1/dt <= (|v| + (l/2)|w| +
  // g dt_max) / r throughout: a bound independent of the duration's square.
  const bool downward = d.gravity.x() == 0 && d.gravity.y() == 0 && d.gravity.z() < 0;
  std::optional<double> floor = d.groundHeight;
  if (d.terrain) floor = std::min(floor.value_or(d.terrain->zMin), d.terrain->zMin);
  if (downward && floor) {
    const BodyState& y = world.state(id);
    const Vec3 w = world.angularVelocity(id);
    const double k0 = 0.5 * y.P.dot(world.velocity(id)) + 0.5 * y.L.dot(w);
    const double drop = std::max(0.0, y.x.z() - *floor + 0.5 * s.diameter);
    const double k = k0 + s.mass * g * drop;
    const double iMin = Eigen::SelfAdjointEigenSolver<Mat3>(s.inertiaBody).eigenvalues().minCoeff();
    const double bound = std::sqrt(2 * k / s.mass) + 0.5 * s.diameter * std::sqrt(2 * k / iMin);
    estimate = std::min(estimate, duration * (bound + g * d.maxStep) / r);
  }
  return std::min(std::max(estimate, atRest), duration / d.minStep);
}

void checkRunLength(const World& world, double duration, const RunLimits& limits,
                    const std::vector<std::string>& where) {
  VF_ASSERT(static_cast<int>(where.size()) == world.bodyCount());
  int worst = -1;
  double worstSteps = 0;
  for (int i = 0; i < world.bodyCount(); ++i) {
    if (world.isStatic(i)) continue;
    const Shape& s = world.shape(i);
    const double speed =
        world.velocity(i).norm() + 0.5 * s.diameter * world.angularVelocity(i).norm();
    if (!(speed <= limits.maxSpeed))
      throw InputError(where[i], guardBodyName(i, s.name) + " starts at " + guardNumber(speed) +
                                     " m/s (|v| + (l/2)|w|), over the limit of " +
                                     guardNumber(limits.maxSpeed) +
                                     " m/s: lower its velocity or angular_velocity, or raise "
                                     "the limit with --max-speed or [simulation] max_speed");
    const double steps = estimatedSteps(world, i, duration);
    if (steps > worstSteps) {
      worstSteps = steps;
      worst = i;
    }
  }
  if (worst < 0 || worstSteps <= static_cast<double>(limits.maxSteps)) return;
  const Shape& s = world.shape(worst);
  const double speed =
      world.velocity(worst).norm() + 0.5 * s.diameter * world.angularVelocity(worst).norm();
  const std::string what = world.def().step.isFixed()
                               ? "the fixed step of " + guardNumber(world.def().step.seconds) + " s"
                               : "a " + guardNumber(s.diameter) + " m body at level " +
                                     std::to_string(s.tree->leafLevel()) + " starting at " +
                                     guardNumber(speed) + " m/s (eq. 20)";
  throw InputError(where[worst],
                   guardBodyName(worst, s.name) + ": " + what + " needs about " +
                       guardNumber(worstSteps) + " steps over " + guardNumber(duration) +
                       " s, over the limit of " + std::to_string(limits.maxSteps) +
                       ": lower the level, the speed, the spin or the duration (or use a longer "
                       "step), or raise the limit with --max-steps or [simulation] max_steps");
}

}  // namespace vf

// The run guard's rules: no run explodes or hangs.
//
// Before a run (checkRunLength): the step rule is global (the fastest body sets everyone's
// step), so one fast, spinning or tiny body can make a run take billions of steps. For each body
// the steps are estimated as if it fell freely for the whole run: with dt = r / (v + g t + g dt)
// (eq. 20 with gravity's increment, r = l / 2^(Lv+1)), the count is the integral of 1 / dt,
// at most T (v + g T / 2 + g maxStep) / r, bounded by T / maxStep below and T / minStep above
// (the world's step bounds), or T / the fixed step. A body that lands moves slower than
// in free fall, so this is an upper bound for rock fall; a run whose estimate exceeds
// RunLimits::maxSteps is refused before any step, naming the body and what to change. A body that
// starts faster than RunLimits::maxSpeed is refused too.
//
// During a run (RunGuard::check, after the impulses of every step):
//   - a non-finite position, orientation or momentum stops the run;
//   - speed: the fastest point of a body moves at most at |v| + (l/2)|w| (eq. 18); above
//     RunLimits::maxSpeed (default 1000 m/s: a rock falling 50 km in vacuum reaches that) the
//     run stops;
//   - energy: gravity conserves E = kinetic + potential (-m g.x) and contacts only remove
//     energy (restitution <= 1, friction), so E should never exceed its value at release. The
//     numerical method does add a little: semi-implicit Euler, the sequential-impulse solver and
//     warm starting. The run stops when E - E_release > energyMargin * S, where the scale
//     S = sum over released bodies of (kinetic energy at release + m |g| l) plus the potential
//     energy released since (max(0, PE_release - PE)): the energy the bodies brought plus what
//     falling gave them, and the energy of lifting each body by its own size so that a body
//     released at rest has a scale. The default margin 0.5 is far above what the method adds
//     (measured: 0 on the shipped scenes, 2e-12 S on barrel, at most 0.015 S over the 1,000
//     random drops of tests/scenario/random_drops_test.cpp) and far below a blow-up, which
//     gains orders of magnitude.
#include "sim/run_guard.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>

#include "sim/core/error.h"
#include "sim/shape/heightfield.h"
#include "sim/world.h"

namespace vf {
namespace {

std::string number(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.4g", x);
  return buf;
}

std::string bodyName(int id, const std::string& shape) {
  return "body " + std::to_string(id) + " (shape '" + shape + "')";
}

}  // namespace

std::string Runaway::message() const {
  const std::string who = bodyName(body, shape) + " at t = " + number(time) + " s: ";
  if (quantity == "non-finite state")
    return who +
           "its state is no longer finite (NaN or infinity); the simulation has left "
           "physics: check for bodies that start inside each other or under the terrain";
  if (quantity == "speed")
    return who + "speed " + number(value) + " m/s (|v| + (l/2)|w|) exceeds the limit of " +
           number(limit) +
           " m/s; the simulation has left physics (a body that started inside another or under "
           "the terrain, or a step too long for the level), or raise the limit with "
           "--max-speed or [simulation] max_speed";
  return who + "total energy rose by " + number(value) + " J, over the allowed " + number(limit) +
         " J (energy at release plus margin); the simulation has left physics (check for "
         "bodies that start inside each other, or use a finer level or a shorter step)";
}

RunawayError::RunawayError(const Runaway& r) : std::runtime_error(r.message()), runaway_(r) {}

std::optional<Runaway> RunGuard::check(const std::vector<BodyInfo>& bodies,
                                       const std::vector<BodyState>& states, const Vec3& gravity,
                                       double time, double dt, const RunLimits& limits) {
  counted_.resize(bodies.size(), 0);
  double energy = 0, potential = 0;
  double topKinetic = -1;
  int topBody = -1;
  for (std::size_t i = 0; i < bodies.size(); ++i) {
    const BodyInfo& b = bodies[i];
    if (!b.moves()) continue;
    const BodyState& y = states[i];
    // Built only when the run stops (the shape's name is a string copy).
    auto stop = [&](const char* quantity, double value, double limit) {
      Runaway r;
      r.body = static_cast<int>(i);
      r.shape = b.shape->name;
      r.time = time;
      r.quantity = quantity;
      r.value = value;
      r.limit = limit;
      return r;
    };
    if (!y.x.allFinite() || !y.q.coeffs().allFinite() || !y.P.allFinite() || !y.L.allFinite())
      return stop("non-finite state", NAN, 0);
    const Vec3 v = velocityOf(b, y), w = angularVelocityOf(b, y);
    // |v| + (l/2)|w|: the speed bound of a body's fastest point (eq. 18).
    const double speed = v.norm() + 0.5 * b.shape->diameter * w.norm();
    if (!(speed <= limits.maxSpeed)) return stop("speed", speed, limits.maxSpeed);
    const double mass = 1 / b.invMass;
    const double kinetic = 0.5 * y.P.dot(v) + 0.5 * y.L.dot(w);
    const double pe = -mass * gravity.dot(y.x + dt * v);
    if (!counted_[i]) {
      counted_[i] = 1;
      releaseEnergy_ += kinetic + pe;
      releasePotential_ += pe;
      scale_ += kinetic + mass * gravity.norm() * b.shape->diameter;
    }
    energy += kinetic + pe;
    potential += pe;
    if (kinetic > topKinetic) {
      topKinetic = kinetic;
      topBody = static_cast<int>(i);
    }
  }
  const double scale = scale_ + std::max(0.0, releasePotential_ - potential);
  const double allowed = limits.energyMargin * scale;
  const double gain = energy - releaseEnergy_;
  if (scale > 0) peakGainRatio_ = std::max(peakGainRatio_, gain / scale);
  if (topBody >= 0 && gain > allowed) {
    Runaway r;
    r.body = topBody;
    r.shape = bodies[topBody].shape->name;
    r.time = time;
    r.quantity = "energy";
    r.value = gain;
    r.limit = allowed;
    return r;
  }
  return std::nullopt;
}

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
      throw InputError(where[i], bodyName(i, s.name) + " starts at " + number(speed) +
                                     " m/s (|v| + (l/2)|w|), over the limit of " +
                                     number(limits.maxSpeed) +
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
                               ? "the fixed step of " + number(world.def().step.seconds) + " s"
                               : "a " + number(s.diameter) + " m body at level " +
                                     std::to_string(s.tree->leafLevel()) + " starting at " +
                                     number(speed) + " m/s (eq. 20)";
  throw InputError(where[worst],
                   bodyName(worst, s.name) + ": " + what + " needs about " + number(worstSteps) +
                       " steps over " + number(duration) + " s, over the limit of " +
                       std::to_string(limits.maxSteps) +
                       ": lower the level, the speed, the spin or the duration (or use a longer "
                       "step), or raise the limit with --max-steps or [simulation] max_steps");
}

}  // namespace vf

// The run guard's rules: no run explodes or hangs.
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

#include <algorithm>
#include <cmath>
#include <optional>

#include "sim/shape/shape.h"

namespace vf {

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

RunGuardListener::RunGuardListener(const RunLimits& limits, const Vec3& gravity)
    : limits_(limits), gravity_(gravity) {}

std::optional<Runaway> RunGuardListener::beforeMove(const StepContext& c) {
  return guard_.check(c.bodies, c.states, gravity_, c.time, c.dt, limits_);
}

}  // namespace vf

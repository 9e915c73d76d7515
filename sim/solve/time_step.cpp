// Eq. 17 asks that a sphere move less than its radius r in one step: dt * v_max <= r, with
// v_max = v_g,max + (l/2) w_max (eq. 18) and r = l / 2^(Lv+1) (eq. 19), giving eq. 20.
//
// The paper has one kind of body per scene; voxfall's scenes mix shapes and levels. We take
// r as the smallest leaf radius term l_i / 2^(Lv_i+1) over moving bodies, and v_max as the
// largest translational speed plus the largest rim speed (l_i/2) w_i over moving bodies: for a
// scene of identical bodies this is eq. 20 exactly, otherwise it is more conservative.
//
// One refinement: voxfall applies gravity before moving the bodies (the README's step order),
// so the speed that moves a body during the step is |v| + |g| dt, not |v|. Solving
// dt (v_max + |g| dt) = r for dt keeps eq. 17 true over the whole step; with g = 0 it is
// eq. 20 unchanged, and for the paper's scenes it differs from eq. 20 by under 5 %.
#include "sim/solve/time_step.h"

#include <algorithm>
#include <cmath>

namespace vf {

double chooseStep(double remaining, double fixedStep, double stable, double minStep, bool& lands,
                  bool& floored) {
  double rule = fixedStep > 0 ? fixedStep : stable;
  floored = fixedStep <= 0 && rule < minStep;  // a runaway body, not the user's choice
  if (floored) rule = minStep;
  lands = false;
  if (!std::isfinite(remaining)) return rule;  // no end in sight: the rule's own step
  // The 1e-9 keeps a fixed step that divides the interval up to rounding from producing one
  // extra tiny step.
  const double n = std::max(1.0, std::ceil(remaining / rule - 1e-9));
  lands = n == 1.0;
  return lands ? remaining : remaining / n;
}

double stableStep(const std::vector<BodyInfo>& bodies, const std::vector<BodyState>& states,
                  const Vec3& gravity, double maxStep) {
  double radius = INFINITY;  // eq. 19, smallest over moving bodies
  double speed = 0;          // largest |v_g|
  double rimSpeed = 0;       // largest (l/2) |w|
  for (std::size_t i = 0; i < bodies.size(); ++i) {
    const BodyInfo& b = bodies[i];
    if (!b.moves()) continue;
    const Shape& s = *b.shape;
    const BodyState& y = states[i];
    radius = std::min(radius, std::ldexp(s.diameter, -(s.tree->leafLevel() + 1)));
    speed = std::max(speed, velocityOf(b, y).norm());
    rimSpeed = std::max(rimSpeed, 0.5 * s.diameter * angularVelocityOf(b, y).norm());
  }
  if (!std::isfinite(radius)) return maxStep;  // nothing moves
  const double v = speed + rimSpeed;
  const double g = gravity.norm();
  // Positive root of g dt^2 + v dt - r = 0 (written to avoid cancellation), or r / v for g = 0.
  double dt;
  if (g > 0)
    dt = 2 * radius / (v + std::sqrt(v * v + 4 * g * radius));
  else
    dt = v > 0 ? radius / v : maxStep;
  if (!(dt > 0)) dt = maxStep;  // non-finite speeds: the integrator freezes such bodies
  return std::min(dt, maxStep);
}

}  // namespace vf

#include "sim/frame_interp.h"

#include <cmath>

#include "sim/core/error.h"
#include "sim/world.h"

namespace vf {

Quat slerpShortArc(const Quat& a, const Quat& b, double s) {
  if (s == 0.0 || a.coeffs() == b.coeffs()) return a;
  double d = a.dot(b);
  const double sign = d < 0 ? -1.0 : 1.0;
  d = std::min(1.0, std::abs(d));
  // Below this angle between the two (half the rotation angle, ~1e-4 rad) the great arc and
  // the chord differ by less than the rounding of the sines: normalised linear interpolation.
  const double theta = std::acos(d);
  double wa = 1 - s, wb = s;
  if (theta > 1e-4) {
    const double sinTheta = std::sin(theta);
    wa = std::sin((1 - s) * theta) / sinTheta;
    wb = std::sin(s * theta) / sinTheta;
  }
  Quat q;
  q.coeffs() = wa * a.coeffs() + (sign * wb) * b.coeffs();
  return q.normalized();
}

BodyState interpolateBody(const BodyState& a, const BodyState& b, double s) {
  BodyState y;
  y.x = a.x + s * (b.x - a.x);
  y.q = slerpShortArc(a.q, b.q, s);
  y.P = a.P + s * (b.P - a.P);
  y.L = a.L + s * (b.L - a.L);
  return y;
}

std::vector<BodyState> sampleSteps(const StepState& before, const StepState* after, double t,
                                   std::vector<char>& active) {
  if (after && t >= after->time - kTimeTolerance) {
    active = after->active;
    return after->states;
  }
  active = before.active;
  if (!after || t <= before.time + kTimeTolerance) return before.states;
  VF_ASSERT(after->states.size() == before.states.size() && after->time > before.time);
  const double s = (t - before.time) / (after->time - before.time);
  std::vector<BodyState> states = before.states;
  for (std::size_t i = 0; i < states.size(); ++i)
    if (before.active[i] && after->active[i])
      states[i] = interpolateBody(before.states[i], after->states[i], s);
  return states;
}

}  // namespace vf

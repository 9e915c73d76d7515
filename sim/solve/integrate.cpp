#include "sim/solve/integrate.h"

namespace vf {

void applyGravity(const std::vector<BodyInfo>& bodies, std::vector<BodyState>& states,
                  const Vec3& gravity, double dt) {
  for (std::size_t i = 0; i < bodies.size(); ++i)
    if (bodies[i].moves()) states[i].P += (dt / bodies[i].invMass) * gravity;
}

Quat quaternionRate(const Vec3& w, const Quat& q) {
  // [0, w] q = [-w.v, s w + w x v] for q = [s, v] (quaternion product of section 2).
  const Vec3 v = q.vec();
  const Vec3 dv = 0.5 * (q.w() * w + w.cross(v));
  return Quat(-0.5 * w.dot(v), dv.x(), dv.y(), dv.z());
}

std::uint64_t integrate(const std::vector<BodyInfo>& bodies, std::vector<BodyState>& states,
                        double dt) {
  std::uint64_t frozen = 0;
  for (std::size_t i = 0; i < bodies.size(); ++i) {
    const BodyInfo& b = bodies[i];
    if (!b.moves()) continue;
    BodyState& y = states[i];
    const Vec3 w = angularVelocityOf(b, y);  // w = I(t)^-1 L, R from q by eq. 6
    const Vec3 x = y.x + dt * b.invMass * y.P;
    const Quat dq = quaternionRate(w, y.q);
    Quat q(y.q.w() + dt * dq.w(), y.q.x() + dt * dq.x(), y.q.y() + dt * dq.y(),
           y.q.z() + dt * dq.z());
    q.normalize();
    if (!x.allFinite() || !q.coeffs().allFinite() || !y.P.allFinite() || !y.L.allFinite()) {
      y.P.setZero();
      y.L.setZero();
      ++frozen;
      continue;
    }
    y.x = x;
    y.q = q;
  }
  return frozen;
}

void freeMotion(const std::vector<BodyInfo>& bodies, std::vector<BodyState>& states,
                const Vec3& gravity, double dt) {
  if (dt <= 0) return;
  applyGravity(bodies, states, gravity, dt);
  integrate(bodies, states, dt);
}

}  // namespace vf

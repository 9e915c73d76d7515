#include "sim/solve/integrate.h"

#include <atomic>

#include "sim/core/worker_pool.h"

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

namespace {

// The rotation by angle |w| dt about w, as a unit quaternion (exp of [0, w dt / 2]).
Quat rotationBy(const Vec3& w, double dt) {
  const double angle = w.norm() * dt;
  if (angle == 0.0) return Quat::Identity();
  return Quat(Eigen::AngleAxisd(angle, w / w.norm()));
}

// One moving body's step; false (and the momenta zeroed, the pose kept) where the new state
// is not finite.
bool integrateBody(const BodyInfo& b, BodyState& y, double dt, RotationUpdate rotation) {
  const Vec3 w = angularVelocityOf(b, y);  // w = I(t)^-1 L, R from q by eq. 6
  // dt (P / M), not dt * velocityOf(b, y): the same quantity rounded as the golden
  // trajectories hold it ((dt / M) P).
  const Vec3 x = y.x + dt * b.invMass * y.P;
  Quat q;
  if (rotation == RotationUpdate::kMidpoint) {
    // Midpoint rule on the rotation group: w is re-evaluated at the orientation reached
    // after half a step, and the whole step rotates exactly by that w.
    const Quat half = (rotationBy(w, 0.5 * dt) * y.q).normalized();
    const Mat3 Rh = half.toRotationMatrix();
    const Vec3 wMid = Rh * b.inertiaBodyInv * Rh.transpose() * y.L;
    q = (rotationBy(wMid, dt) * y.q).normalized();
  } else {
    const Quat dq = quaternionRate(w, y.q);
    q = Quat(y.q.w() + dt * dq.w(), y.q.x() + dt * dq.x(), y.q.y() + dt * dq.y(),
             y.q.z() + dt * dq.z());
    q.normalize();
  }
  if (!x.allFinite() || !q.coeffs().allFinite() || !y.P.allFinite() || !y.L.allFinite()) {
    y.P.setZero();
    y.L.setZero();
    return false;
  }
  y.x = x;
  y.q = q;
  return true;
}

}  // namespace

std::uint64_t integrate(const std::vector<BodyInfo>& bodies, std::vector<BodyState>& states,
                        double dt, RotationUpdate rotation, WorkerPool* pool) {
  std::atomic<std::uint64_t> frozen{0};
  WorkerPool::forRanges(
      pool, static_cast<int>(bodies.size()), WorkerPool::kBodiesPerRange, [&](int lo, int hi) {
        for (int i = lo; i < hi; ++i)
          if (bodies[i].moves() && !integrateBody(bodies[i], states[i], dt, rotation)) ++frozen;
      });
  return frozen;
}

void freeMotion(const std::vector<BodyInfo>& bodies, std::vector<BodyState>& states,
                const Vec3& gravity, double dt) {
  if (dt <= 0) return;
  applyGravity(bodies, states, gravity, dt);
  integrate(bodies, states, dt);
}

}  // namespace vf

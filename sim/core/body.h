// What every step stage reads: the mutable per-body state array, the per-body constants beside
// it, and the contact materials. Stage headers include this, never sim/world.h. The shape is
// only named here (sim/core sits below sim/shape, docs/architecture.md "Layers"): a stage that
// reads a body's mesh, tree or mass includes sim/shape/shape.h itself.
#pragma once

#include <memory>

#include "sim/core/math.h"

namespace vf {

struct Shape;

// Rigid-body state y = {x, q, P, L} (eqs. 1-7): centre of mass (m), unit orientation
// quaternion (body -> world), linear momentum (kg m/s), angular momentum (kg m^2/s).
struct BodyState {
  Vec3 x = Vec3::Zero();
  Quat q = Quat::Identity();
  Vec3 P = Vec3::Zero();
  Vec3 L = Vec3::Zero();
};

// Restitution eps and kinetic friction mu per kind of contact pair (section 5 defaults).
struct ContactMaterial {
  double restitutionBodyBody = 0.5;
  double restitutionBodyGround = 0.3;
  double frictionBodyBody = 0.3;
  double frictionBodyGround = 0.8;
};

struct BodyInfo {
  std::shared_ptr<const Shape> shape;
  double invMass = 0;                  // 1/M, 0 for static bodies
  Mat3 inertiaBodyInv = Mat3::Zero();  // I_body^-1, zero for static bodies
  bool isStatic = false;
  bool active = true;         // released (emitter bodies join later)
  double releaseTime = 0;     // s
  double dropHeight = -1;     // m; < 0: release where placed (see BodyDef)
  bool clearRelease = false;  // raised at release if born inside another body (see BodyDef)
  bool sleeping = false;      // at rest: frozen until touched (solve/sleep.h)
  double restTime = 0;        // s the body has been slower than the sleep threshold
  int sleepIsland = -1;       // lowest id of the island it fell asleep with
  // Released and not static: has mass, gravity and energy, awake or asleep.
  bool dynamic() const { return active && !isStatic; }
  // Dynamic and awake: what the step's stages move.
  bool moves() const { return dynamic() && !sleeping; }
};

// The one place the derived quantities of a body are computed (style.md: one formula, not five
// copies that drift apart).
// World-frame inverse inertia I(t)^-1 = R I_body^-1 R^T (eq. 6), zero for static bodies.
inline Mat3 inverseInertiaWorld(const BodyInfo& b, const BodyState& y) {
  const Mat3 R = y.q.toRotationMatrix();
  // Assigned, not constructed: Eigen then takes the product path (and rounding) that the
  // golden trajectories and checksums hold.
  Mat3 invI;
  invI = R * b.inertiaBodyInv * R.transpose();
  return invI;
}
// Velocity of the centre of mass v = P / M, m/s.
inline Vec3 velocityOf(const BodyInfo& b, const BodyState& y) { return y.P * b.invMass; }
// Angular velocity w = I(t)^-1 L, rad/s, world frame. Written as one chained product (Eigen
// then rounds differently from inverseInertiaWorld(b, y) * L): this is the form that the golden
// trajectories and checksums hold.
inline Vec3 angularVelocityOf(const BodyInfo& b, const BodyState& y) {
  const Mat3 R = y.q.toRotationMatrix();
  return R * b.inertiaBodyInv * R.transpose() * y.L;
}

}  // namespace vf

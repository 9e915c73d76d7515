// Rolling resistance, constant-torque type (Project Chrono's NSC rolling friction, LIGGGHTS
// "cdt"; Azzoni et al. 1995 for rock fall, whose tan(phi_r) is mu_r here).
//
// Why a separate pass after the impulse solve rather than a row of the solver: friction has by
// then matched the contact point's velocity (rolling without slip where the Coulomb cone
// allows), so the rolling spin is known, and the torque only needs the step's normal impulse.
// Removing spin leaves the contact point slipping; the next step's friction takes it back out
// of the linear velocity, so for a rolling body the angular momentum about the contact point,
// (m h + I/h) v, falls by mu_r h N dt per step: for a sphere on level ground
// a = 5/7 mu_r g and the stopping distance is d = 7 v0^2 / (10 mu_r g) (Azzoni et al. 1995;
// tests/scenario/rockfall_test.cpp checks it).
//
// Alternatives rejected: a rotational spring-dashpot (LIGGGHTS epsd, Rockable) needs a
// stiffness nobody has published for rock on soil; velocity-dependent scarring friction
// (RAMMS) does no work on a rock that rolls without slip (shared/rockfall-models.md).
#include "sim/solve/rolling_resistance.h"

#include <cmath>

namespace vf {

int applyRollingResistance(const std::vector<Contact>& contacts,
                           const std::vector<double>& normalImpulses,
                           const std::vector<BodyInfo>& bodies, std::vector<BodyState>& states,
                           const GroundMap& ground) {
  int braked = 0;
  const std::size_t n = contacts.size();
  // Ground contacts come per body in body order (narrow_phase.cpp), but nothing here relies
  // on it: each run of one body's contacts is summed, in contact order (deterministic).
  std::vector<double> limit(bodies.size(), 0.0);
  std::vector<Vec3> normal(bodies.size(), Vec3::Zero());
  for (std::size_t k = 0; k < n; ++k) {
    const Contact& c = contacts[k];
    const double jn = normalImpulses[k];
    if (c.b != kGround || !(jn > 0)) continue;
    const double muR = ground.at(c.point.x(), c.point.y()).rollingResistance;
    if (muR <= 0) continue;
    const double lever = -(c.point - states[c.a].x).dot(c.normal);
    if (lever <= 0) continue;
    limit[c.a] += muR * lever * jn;
    normal[c.a] += jn * c.normal;
  }
  for (std::size_t i = 0; i < bodies.size(); ++i) {
    if (!(limit[i] > 0) || !bodies[i].moves()) continue;
    BodyState& y = states[i];
    // Written out rather than inverseInertiaWorld(): constructed, Eigen rounds this product
    // differently, and the rock fall scenes' checksums and the README's maps were made so.
    const Mat3 R = y.q.toRotationMatrix();
    const Mat3 invI = R * bodies[i].inertiaBodyInv * R.transpose();
    const Vec3 nHat = normal[i].normalized();
    const Vec3 w = invI * y.L;
    const Vec3 wt = w - w.dot(nHat) * nHat;
    const double spin = wt.norm();
    if (spin == 0.0) continue;
    const Vec3 t = wt / spin;
    const double stopAll = spin / t.dot(invI * t);  // the angular impulse that ends the rolling
    y.L -= std::min(stopAll, limit[i]) * t;
    ++braked;
  }
  return braked;
}

}  // namespace vf

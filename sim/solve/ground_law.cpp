// STONE's ground-contact law on a rigid body: flight, bounce and rolling.
//
// STONE (Guzzetti, Crosta, Detti & Agliardi 2002, Computers & Geosciences 28(9):1079-1093),
// whose per-lithology coefficients the presets are (ground_material.cpp), moves a rock in three
// modes, as its GRASS implementation r.stone does it (OSGeo grass-addons src/raster/r.stone,
// points.c and fixed_parameters.c at commit c6085084c93b):
//  - flight: a parabola until the rock meets the ground;
//  - bounce: in the plane of the ground, the normal velocity becomes -Rn v_n and the tangential
//    velocity Rt v_t; but a bounce shorter than 3 m (from the previous bounce, or the release)
//    at a speed under 5 m/s instead starts rolling;
//  - rolling: the rock decelerates by its rolling friction tan(phi_r) on every triangle of the
//    ground until a new triangle lies more than 1 cm below it, when it flies again.
// Here a rigid body meets a voxelised surface instead of a point meeting a plane, so:
//  - Rn is eq. 15's restitution of the ground contacts (the solver, unchanged);
//  - a landing is the first step in ground contact after a flight, and a flight begins when the
//    body's sphere tree is 1 cm clear of the ground (clearOfGround): a rock rolling over
//    voxel bumps or onto a new DEM facet keeps rolling, as STONE's does;
//  - a bounce keeps at most Rt of the incoming tangential velocity of the centre of mass (the
//    solver's Coulomb friction may already have taken more: never restored), and the spin is
//    scaled with it, so a rock that lands rolling leaves rolling; kinetic energy only falls;
//  - while rolling, the friction is a torque (rolling resistance, below), as in Azzoni et al.
//    1995, whose tan(phi_r) is mu_r here.
//
// Rolling resistance, constant-torque type (Project Chrono's NSC rolling friction, LIGGGHTS
// "cdt"). Why a separate pass after the impulse solve rather than a row of the solver: friction
// has by then matched the contact point's velocity (rolling without slip where the Coulomb cone
// allows), so the rolling spin is known, and the torque only needs the normal force. Removing
// spin leaves the contact point slipping; the next step's friction takes it back out of the
// linear velocity, so for a rolling body the angular momentum about the contact point,
// (m h + I/h) v, falls by mu_r h N dt per step: for a sphere on level ground a = 5/7 mu_r g and
// the stopping distance is d = 7 v0^2 / (10 mu_r g) (Azzoni et al. 1995;
// tests/scenario/rockfall_test.cpp checks it). N is the sustained normal force: a body's summed
// normal impulse counts up to its weight's share, m |g.n| dt. An impact's impulse (a 60 kg
// block landing at 8 m/s: about 500 N s, against 0.6 N s of weight in a millisecond step) is
// not rolling: fed to mu_r h N it would end all spin at every landing, and stop the Tschamut
// blocks about half way (docs/validation.md, "Tschamut 2014").
//
// Alternatives rejected: a rotational spring-dashpot (LIGGGHTS epsd, Rockable) needs a
// stiffness nobody has published for rock on soil; velocity-dependent scarring friction
// (RAMMS) does no work on a rock that rolls without slip (shared/rockfall-models.md).
#include "sim/solve/ground_law.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "sim/shape/shape.h"

namespace vf {

void GroundLaw::beforeSolve(const std::vector<BodyInfo>& bodies,
                            const std::vector<BodyState>& states) {
  if (modes_.size() < bodies.size()) modes_.resize(bodies.size());
  for (std::size_t i = 0; i < bodies.size(); ++i) {
    if (!bodies[i].moves()) continue;
    modes_[i].incoming = velocityOf(bodies[i], states[i]);
    modes_[i].incomingSpin = states[i].L;
  }
}

GroundLawStats GroundLaw::afterSolve(const std::vector<Contact>& contacts,
                                     const std::vector<double>& normalImpulses,
                                     const std::vector<BodyInfo>& bodies,
                                     std::vector<BodyState>& states, const GroundMap& ground,
                                     const Vec3& gravity, double dt, const Heightfield* terrain,
                                     std::optional<double> floor) {
  GroundLawStats stats;
  if (modes_.size() < bodies.size()) modes_.resize(bodies.size());
  const std::size_t nb = bodies.size();
  sumGroundContacts(nb, contacts, normalImpulses, states, ground);
  for (std::size_t i = 0; i < nb; ++i) {
    const BodyInfo& b = bodies[i];
    if (!b.moves()) continue;
    BodyState& y = states[i];
    Mode& mode = modes_[i];
    if (!mode.seen) mode.seen = true, mode.lastBounce = y.x;  // STONE: the release point
    if (!(impulse_[i] > 0)) {  // no ground contact: flying once 1 cm clear
      if (!mode.airborne && clearOfGround(b, y, terrain, floor, kStoneLiftOff, mode.nearLeaf))
        mode.airborne = true;
      continue;
    }
    const Vec3 nHat = normal_[i].normalized();
    if (mode.airborne) {  // a landing
      mode.airborne = false;
      if (!(stoneImpulse_[i] > 0)) continue;  // on slip ground only: the slip law's (no bounce)
      const bool shortAndSlow = (y.x - mode.lastBounce).norm() < kStoneShortBounce &&
                                mode.incoming.norm() < kStoneRollSpeed;
      if (shortAndSlow) {
        ++stats.rolls;
      } else {
        ++stats.bounces;
        stats.bounced.push_back(static_cast<int>(i));
        mode.lastBounce = y.x;
        const Vec3 vIn = mode.incoming - mode.incoming.dot(nHat) * nHat;
        const Vec3 v = velocityOf(b, y);
        const Vec3 vn = v.dot(nHat) * nHat, vt = v - vn;
        const double keep = rt_[i] / impulse_[i] * vIn.norm();
        if (vt.norm() > keep) {
          const double s = keep / vt.norm();
          y.P = (vn + s * vt) / b.invMass;
          y.L *= s;
        }
        continue;  // a bounce is not rolling: no rolling resistance this step
      }
    }
    if (!(limit_[i] > 0)) continue;
    // Rolling resistance with the sustained normal force (see the top of this file).
    const double sustained = std::abs(gravity.dot(nHat)) * dt / b.invMass;
    const double brake = limit_[i] * std::min(1.0, sustained / impulse_[i]);
    const Mat3 invI = inverseInertiaWorld(b, y);
    const Vec3 w = invI * y.L;
    const Vec3 wt = w - w.dot(nHat) * nHat;
    const double spin = wt.norm();
    if (spin == 0.0) continue;
    const Vec3 t = wt / spin;
    const double stopAll = spin / t.dot(invI * t);  // the angular impulse that ends the rolling
    y.L -= std::min(stopAll, brake) * t;
    ++stats.braked;
  }
  return stats;
}

void GroundLaw::sumGroundContacts(std::size_t nb, const std::vector<Contact>& contacts,
                                  const std::vector<double>& normalImpulses,
                                  const std::vector<BodyState>& states, const GroundMap& ground) {
  // Per body, summed over its ground contacts in contact order (deterministic): the rolling
  // limit sum mu_r,k h_k jn_k, the normal impulse (all ground contacts, and those on STONE
  // materials), the impulse-weighted normal and Rt. A contact on a slip material (slip_law.cpp)
  // keeps the body out of flight but takes no STONE bounce or brake: it counts with Rt = 1.
  limit_.assign(nb, 0.0);
  impulse_.assign(nb, 0.0);
  stoneImpulse_.assign(nb, 0.0);
  rt_.assign(nb, 0.0);
  normal_.assign(nb, Vec3::Zero());
  for (std::size_t k = 0; k < contacts.size(); ++k) {
    const Contact& c = contacts[k];
    const double jn = normalImpulses[k];
    if (c.b != kGround || !(jn > 0)) continue;
    const GroundCoefficients m = ground.coefficientsAt(c.point.x(), c.point.y());
    impulse_[c.a] += jn;
    normal_[c.a] += jn * c.normal;
    if (m.law == GroundLawKind::kSlip) {
      rt_[c.a] += jn;
      continue;
    }
    const double lever = -(c.point - states[c.a].x).dot(c.normal);
    if (m.rollingResistance > 0 && lever > 0) limit_[c.a] += m.rollingResistance * lever * jn;
    stoneImpulse_[c.a] += jn;
    rt_[c.a] += m.tangentialRestitution * jn;
  }
}

bool clearOfGround(const BodyInfo& b, const BodyState& y, const Heightfield* terrain,
                   std::optional<double> floor, double height, std::uint32_t& hint) {
  const SphereTree& tree = *b.shape->tree;
  const SphereTreeLevel& leaves = tree.leaves();
  const double r = leaves.radius;
  const Mat3 R = y.q.toRotationMatrix();
  const auto n = static_cast<std::uint32_t>(leaves.centers.size());
  // Every leaf centre lies over the square of the bounding sphere (widened against rounding),
  // so the terrain's normals there have z >= nzMin. A leaf v > 0 above the facet under it with
  // v nzMin - r > height is then clear without its own normal: v nz >= v nzMin, and rounding is
  // monotonic, so the computed (v nz) - r is no less than the computed (v nzMin) - r.
  const double nzMin =
      terrain ? terrain->minNormalZNear(y.x.x(), y.x.y(), tree.boundingRadius * (1 + 1e-9) + 1e-9)
              : 1.0;
  // Whether leaf k's gap is at most `height`: its centre's height above the floor, or along
  // the normal above the facet under it, less the radius.
  auto within = [&](std::uint32_t k) {
    const Vec3 c = y.x + R * leaves.centers[k];
    if (floor && c.z() - *floor - r <= height) return true;
    if (!terrain) return false;
    const double h = terrain->heightAt(c.x(), c.y());
    if (std::isnan(h)) return false;
    const double v = c.z() - h;
    if (v > 0 && v * nzMin - r > height) return false;
    return v * terrain->normalAt(c.x(), c.y()).z() - r <= height;
  };
  // A rolling body stays near the ground for many steps, mostly by the same leaves: the one
  // that answered last time first (with 500 leaves a step, testing them all is a third of a
  // rock's step on the Tyrol slope).
  if (hint < n && within(hint)) return false;
  auto found = [&](std::uint32_t k) {
    if (k == hint || !within(k)) return false;
    hint = k;
    return true;
  };
  if (tree.leafLevel() == 0) {  // a one-level tree: its leaves alone
    for (std::uint32_t k = 0; k < n; ++k)
      if (found(k)) return false;
    return true;
  }
  // The others through the tree, from the bounding sphere down. Every leaf sphere lies in each
  // of its ancestors' spheres (sphere_tree.h; up to the rounding slack s), so a leaf centre c
  // under a node of centre C and radius Rn has c.z >= C.z - Rn - s + r and lies over the
  // node's square, where the surface is no higher than B = surfaceBoundNear: its height above
  // the facet is v >= V = C.z - Rn - s + r - B and, with V > 0, its gap v nz - r >= V nzMin - r;
  // above the floor, C.z - Rn - s - floor. A node whose bounds exceed `height` by 1e-9 m (the
  // leaf gaps' own rounding is about 1e-13 of the heights) holds no leaf within it.
  const double slack = roundingSlack(y.x, tree.boundingRadius);
  auto nodeClear = [&](const Vec3& C, double Rn) {
    const double low = C.z() - Rn - slack;
    if (floor && !(low - *floor > height + 1e-9)) return false;
    if (!terrain) return true;
    const double V = low + r - terrain->surfaceBoundNear(C.x(), C.y(), Rn + slack);
    return V > 0 && V * nzMin - r > height + 1e-9;
  };
  if (nodeClear(y.x, tree.boundingRadius)) return true;
  const int leafLevel = tree.leafLevel();
  // Whether a leaf under node i of `level` (not the leaf level) is within `height`.
  auto anyWithin = [&](auto& self, int level, std::uint32_t i) -> bool {
    const SphereTreeLevel& lv = tree.levels[level];
    const SphereTreeLevel& next = tree.levels[level + 1];
    for (std::uint32_t k = lv.childBegin[i]; k < lv.childBegin[i + 1]; ++k) {
      if (level + 1 == leafLevel) {
        if (found(k)) return true;
      } else if (!nodeClear(y.x + R * next.centers[k], next.radius) && self(self, level + 1, k)) {
        return true;
      }
    }
    return false;
  };
  return !anyWithin(anyWithin, 0, 0);  // level 0's one node: the bounding sphere stands for it
}

}  // namespace vf

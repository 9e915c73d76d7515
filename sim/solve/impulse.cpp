// Sequential impulses.
//
// The paper gives the impulse of one contact (eq. 15) but not how the many leaf contacts of a
// body pair combine. Applying eq. 15 once to each contact in turn over-reacts (every contact of
// a flat face sees the full approach speed) and makes resting bodies jitter; solving all of
// them simultaneously is a complementarity problem. voxfall does what sequential-impulse
// engines do (Gauss-Seidel on the contact velocities):
//   - per contact, the target normal velocity is -eps * (approach speed at the start of the
//     step) if the contact approaches faster than `restingSpeed`, else 0 (resting contact);
//   - several passes over all contacts in their fixed order; each pass computes the relative
//     velocity afresh and applies the impulse that reaches the target, eq. 15's
//     j = (target - vRel) / K, where K is eq. 15's denominator;
//   - the sum of a contact's normal impulses is kept >= 0 (contacts push, never pull), so a
//     later pass may take back part of an earlier impulse that others made unnecessary;
//   - friction: impulses along two tangents opposing the tangential velocity, with their sum
//     clamped to the Coulomb disc |J_t| <= mu J_n (kinetic mu).
//   - warm starting: a contact that existed in the previous step (same body pair, same two
//     leaf spheres) and was resting there (no restitution target) starts from the impulse it
//     ended with, scaled by min(1, dt / dt_previous). A face resting on a face has hundreds of
//     leaf contacts whose centre-to-centre normals tilt by up to 45 degrees; from a cold start
//     a dozen passes leave a residual that shows as jitter, while warm-started passes converge
//     over steps. (Passes always run forward: alternating sweeps were tried and converged
//     worse on a flat landing.) The scale never exceeds 1 because part of an impulse
//     corrects velocity errors and does not grow with dt: after a very short step (a release
//     time just after a frame time), scaling up by the step ratio would blow bodies apart.
// A single new contact gets exactly eq. 15 in the first pass, and later passes change nothing.
#include "sim/solve/impulse.h"

#include <algorithm>
#include <cmath>

namespace vf {

double inverseEffectiveMass(double invMassA, const Mat3& invInertiaA, const Vec3& ra,
                            double invMassB, const Mat3& invInertiaB, const Vec3& rb,
                            const Vec3& d) {
  return invMassA + invMassB +
         d.dot((invInertiaA * ra.cross(d)).cross(ra) + (invInertiaB * rb.cross(d)).cross(rb));
}

double restitutionImpulse(double vRel, double eps, double inverseEffectiveMass) {
  return -(1 + eps) * vRel / inverseEffectiveMass;
}

namespace {

struct Motion {  // velocities during the solve
  Vec3 v = Vec3::Zero();
  Vec3 w = Vec3::Zero();
  Mat3 invI = Mat3::Zero();  // world frame: R I_body^-1 R^T
  double invMass = 0;
};

struct Row {  // one contact, prepared
  ContactKey key;
  int a, b;   // motion indices; b may be the ground slot
  Vec3 ra, rb, n, t1, t2;
  double kn, kt1, kt2;  // 1 / inverse effective masses
  double target;        // wanted normal velocity
  double mu;
  double jn = 0, jt1 = 0, jt2 = 0;  // accumulated impulses
};

// Two unit tangents completing n to a right-handed basis (fixed choice: deterministic).
void tangents(const Vec3& n, Vec3& t1, Vec3& t2) {
  const Vec3 helper = std::abs(n.x()) < 0.57 ? Vec3::UnitX() : Vec3::UnitY();
  t1 = n.cross(helper).normalized();
  t2 = n.cross(t1);
}

Vec3 pointVelocity(const Motion& m, const Vec3& r) { return m.v + m.w.cross(r); }

void applyImpulse(Motion& a, Motion& b, const Row& row, const Vec3& J) {
  a.v += a.invMass * J;
  a.w += a.invI * row.ra.cross(J);
  b.v -= b.invMass * J;
  b.w -= b.invI * row.rb.cross(J);
}

}  // namespace

void solveContacts(const std::vector<Contact>& contacts, const std::vector<BodyInfo>& bodies,
                   std::vector<BodyState>& states, const SolverSettings& settings,
                   ContactCache& cache) {
  if (contacts.empty()) {
    cache.impulses.clear();
    cache.dt = settings.dt;
    return;
  }
  const int n = static_cast<int>(bodies.size());
  const int groundSlot = n;  // an immovable extra slot for the floor
  std::vector<Motion> motion(n + 1);
  for (int i = 0; i < n; ++i) {
    if (!bodies[i].moves()) continue;
    const BodyState& y = states[i];
    const Mat3 R = y.q.toRotationMatrix();
    Motion& m = motion[i];
    m.invMass = bodies[i].invMass;
    m.invI = R * bodies[i].inertiaBodyInv * R.transpose();
    m.v = y.P * m.invMass;
    m.w = m.invI * y.L;
  }

  const ContactMaterial& mat = settings.material;
  std::vector<Row> rows;
  rows.reserve(contacts.size());
  for (const Contact& c : contacts) {
    Row r;
    r.key = ContactKey{c.a, c.b, c.leafA, c.leafB};
    r.a = c.a;
    r.b = c.b == kGround ? groundSlot : c.b;
    r.ra = c.point - states[c.a].x;
    r.rb = c.b == kGround ? Vec3::Zero() : Vec3(c.point - states[c.b].x);
    r.n = c.normal;
    tangents(r.n, r.t1, r.t2);
    const Motion& A = motion[r.a];
    const Motion& B = motion[r.b];
    auto k = [&](const Vec3& d) {
      return 1.0 / inverseEffectiveMass(A.invMass, A.invI, r.ra, B.invMass, B.invI, r.rb, d);
    };
    r.kn = k(r.n);
    r.kt1 = k(r.t1);
    r.kt2 = k(r.t2);
    if (!std::isfinite(r.kn)) continue;  // both sides immovable
    const bool ground = c.b == kGround || bodies[c.a].isStatic || bodies[c.b].isStatic;
    const double eps = ground ? mat.restitutionBodyGround : mat.restitutionBodyBody;
    r.mu = ground ? mat.frictionBodyGround : mat.frictionBodyBody;
    const double vRel = r.n.dot(pointVelocity(A, r.ra) - pointVelocity(B, r.rb));
    r.target = vRel < -settings.restingSpeed ? -eps * vRel : 0.0;  // v_rel+ = -eps v_rel-
    rows.push_back(r);
  }

  // Warm start from the previous step's impulses (cache sorted by key: binary search).
  const double scale = cache.dt > 0 ? std::min(1.0, settings.dt / cache.dt) : 0.0;
  for (Row& r : rows) {
    const auto it = std::lower_bound(
        cache.impulses.begin(), cache.impulses.end(), r.key,
        [](const CachedImpulse& c, const ContactKey& k) { return c.key < k; });
    if (it == cache.impulses.end() || it->key != r.key) continue;
    r.jn = it->normal * scale;
    r.jt1 = it->tangent1 * scale;
    r.jt2 = it->tangent2 * scale;
    applyImpulse(motion[r.a], motion[r.b], r, r.jn * r.n + r.jt1 * r.t1 + r.jt2 * r.t2);
  }

  const int count = static_cast<int>(rows.size());
  for (int pass = 0; pass < settings.iterations; ++pass) {
    for (int k = 0; k < count; ++k) {
      Row& r = rows[k];
      Motion& A = motion[r.a];
      Motion& B = motion[r.b];
      // Normal: eq. 15 towards the target, accumulated impulse kept >= 0.
      const Vec3 dv = pointVelocity(A, r.ra) - pointVelocity(B, r.rb);
      const double vn = r.n.dot(dv);
      const double jn = std::max(r.jn + (r.target - vn) * r.kn, 0.0);
      const double djn = jn - r.jn;
      r.jn = jn;
      if (djn != 0.0) applyImpulse(A, B, r, djn * r.n);
      // Friction: stop the tangential slip, within the Coulomb disc of the current jn.
      const Vec3 dvt = pointVelocity(A, r.ra) - pointVelocity(B, r.rb);
      double jt1 = r.jt1 - r.t1.dot(dvt) * r.kt1;
      double jt2 = r.jt2 - r.t2.dot(dvt) * r.kt2;
      const double limit = r.mu * r.jn;
      const double jt = std::sqrt(jt1 * jt1 + jt2 * jt2);
      if (jt > limit) {
        const double s = limit / jt;
        jt1 *= s;
        jt2 *= s;
      }
      const Vec3 J = (jt1 - r.jt1) * r.t1 + (jt2 - r.jt2) * r.t2;
      r.jt1 = jt1;
      r.jt2 = jt2;
      applyImpulse(A, B, r, J);
    }
  }

  // Only resting contacts seed the next step: an impact's impulse belongs to its own step, and
  // re-applied while the bodies separate it would throw them apart.
  cache.dt = settings.dt;
  cache.impulses.clear();
  for (const Row& r : rows)
    if (r.target == 0.0) cache.impulses.push_back({r.key, r.jn, r.jt1, r.jt2});
  std::sort(cache.impulses.begin(), cache.impulses.end(),
            [](const CachedImpulse& x, const CachedImpulse& y) { return x.key < y.key; });

  // P1 += J, L1 += r1 x J for the total impulse of every contact (and the opposite on body 2).
  for (const Row& r : rows) {
    const Vec3 J = r.jn * r.n + r.jt1 * r.t1 + r.jt2 * r.t2;
    if (r.a < n && bodies[r.a].moves()) {
      states[r.a].P += J;
      states[r.a].L += r.ra.cross(J);
    }
    if (r.b < n && bodies[r.b].moves()) {
      states[r.b].P -= J;
      states[r.b].L -= r.rb.cross(J);
    }
  }
}

}  // namespace vf

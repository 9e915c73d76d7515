// Eq. 15 and the sequential-impulse solver against hand computations.
#include "sim/solve/impulse.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>

#include "sim/collide/contact_reduction.h"
#include "sim/collide/narrow_phase.h"
#include "sim/core/prng.h"
#include "sim/core/worker_pool.h"
#include "tests/support/test_world.h"

namespace vf {
namespace {

// A dynamic body of shape s, as World makes it from a BodyDef.
BodyInfo bodyOf(std::shared_ptr<const Shape> s) {
  BodyInfo b;
  b.shape = s;
  b.invMass = 1 / s->mass;
  b.inertiaBodyInv = s->inertiaBodyInv;
  return b;
}

struct OneBody {
  std::vector<BodyInfo> bodies;
  std::vector<BodyState> states;
  explicit OneBody(std::shared_ptr<const Shape> s) {
    bodies.push_back(bodyOf(s));
    states.emplace_back();
  }
};

// The box of the multi-pass tests, slightly tilted, and the height of its centre when it sinks
// 2 mm into the floor.
struct TiltedBox {
  std::shared_ptr<const Shape> shape = test::boxShape(0.4, 0.3, 0.2, 800, 3);
  double z0 = test::restOffset(*shape) - 0.002;
  Quat q = Quat(Eigen::AngleAxisd(0.02, Vec3(1, 2, 0).normalized()));
};

TEST(Impulse, OffCentreGroundContactMatchesHandComputation) {
  // Box 0.4 x 0.2 x 0.2, contact below the centre at r = (d, 0, -h), normal +z.
  // By hand: r x n = (0, -d, 0); I^-1 (r x n) = (0, -d/Iyy, 0); (..) x r = (d h/Iyy, 0, d^2/Iyy);
  // so K = 1/m + d^2/Iyy and j = -(1 + eps) v_rel / K (eq. 15). Then P_z += j, L_y += -d j.
  auto s = test::boxShape(0.4, 0.2, 0.2, 800, 2);
  OneBody w(s);
  const double m = s->mass, Iyy = m * (0.4 * 0.4 + 0.2 * 0.2) / 12;  // closed form, box
  const double vz = -2.0, d = 0.15, h = 0.1, eps = 0.3;
  w.states[0].P = Vec3(0, 0, m * vz);
  Contact c;
  c.a = 0;
  c.b = kGround;
  c.point = Vec3(d, 0, -h);
  c.normal = Vec3::UnitZ();
  SolverSettings settings;
  settings.dt = 0.01;
  ContactCache cache;
  settings.material.restitutionBodyGround = eps;
  settings.material.frictionBodyGround = 0;
  settings.iterations = 1;
  solveContacts({c}, w.bodies, w.states, settings, cache);
  const double K = 1 / m + d * d / Iyy;
  const double j = -(1 + eps) * vz / K;
  EXPECT_NEAR(w.states[0].P.z(), m * vz + j, 1e-9 * m);
  EXPECT_NEAR(w.states[0].L.y(), -d * j, 1e-9 * m);
  EXPECT_NEAR(w.states[0].L.x(), 0, 1e-12);
  EXPECT_NEAR(inverseEffectiveMass(1 / m, s->inertiaBodyInv, c.point, 0, Mat3::Zero(), Vec3::Zero(),
                                   c.normal),
              K, 1e-9 * K);
  // The contact point now separates at -eps times its approach speed (v_rel+ = -eps v_rel-).
  const Vec3 v = w.states[0].P / m;
  const Vec3 omega = s->inertiaBodyInv * w.states[0].L;
  EXPECT_NEAR((v + omega.cross(c.point)).z(), -eps * vz, 1e-9);
}

TEST(Impulse, HeadOnCollisionOfEqualBodiesFollowsNewtonsLaw) {
  // Two equal boxes, centres on the x axis, contact midway, approaching at 3 and -1 m/s.
  // Newton's restitution law with momentum conservation (independent of eq. 15):
  // v1' = ((1 - e) v1 + (1 + e) v2) / 2, v2' = ((1 + e) v1 + (1 - e) v2) / 2.
  auto s = test::boxShape(0.2, 0.2, 0.2, 800, 2);
  std::vector<BodyInfo> bodies(2);
  std::vector<BodyState> states(2);
  for (int i = 0; i < 2; ++i) {
    bodies[i].shape = s;
    bodies[i].invMass = 1 / s->mass;
    bodies[i].inertiaBodyInv = s->inertiaBodyInv;
  }
  const double v1 = 3, v2 = -1, e = 0.5, m = s->mass;
  states[0].x = Vec3(-0.1, 0, 0);
  states[1].x = Vec3(0.1, 0, 0);
  states[0].P = Vec3(m * v1, 0, 0);
  states[1].P = Vec3(m * v2, 0, 0);
  Contact c;
  c.a = 0;
  c.b = 1;
  c.point = Vec3::Zero();
  c.normal = Vec3(-1, 0, 0);  // force on body 1 (a) points from b to a
  SolverSettings settings;
  settings.dt = 0.01;
  ContactCache cache;
  settings.material.restitutionBodyBody = e;
  solveContacts({c}, bodies, states, settings, cache);
  EXPECT_NEAR(states[0].P.x() / m, ((1 - e) * v1 + (1 + e) * v2) / 2, 1e-12);
  EXPECT_NEAR(states[1].P.x() / m, ((1 + e) * v1 + (1 - e) * v2) / 2, 1e-12);
  EXPECT_NEAR(states[0].L.norm() + states[1].L.norm(), 0, 1e-12);  // central impact
}

TEST(Impulse, FrictionIsBoundedByCoulombAndStopsSlowSlip) {
  // A box sliding at 1 m/s along x while pressed into the ground at 1 m/s; contact under the
  // centre of mass. Tangential impulse magnitude is at most mu * j_n (kinetic Coulomb).
  auto s = test::boxShape(0.2, 0.2, 0.2, 800, 2);
  const double m = s->mass;
  for (double mu : {0.1, 5.0}) {
    OneBody w(s);
    w.states[0].P = m * Vec3(1.0, 0, -1.0);
    Contact c;
    c.a = 0;
    c.point = Vec3(0, 0, -0.1);
    c.normal = Vec3::UnitZ();
    SolverSettings settings;
    settings.dt = 0.01;
    ContactCache cache;
    settings.material.restitutionBodyGround = 0;
    settings.material.frictionBodyGround = mu;
    solveContacts({c}, w.bodies, w.states, settings, cache);
    const Vec3 dP = w.states[0].P - m * Vec3(1.0, 0, -1.0);
    const double jn = dP.z(), jt = std::hypot(dP.x(), dP.y());
    EXPECT_GT(jn, 0);
    EXPECT_LE(jt, mu * jn * (1 + 1e-12));
    EXPECT_LT(dP.x(), 0);  // opposes the slip
    if (mu == 0.1) {
      EXPECT_NEAR(jt, mu * jn, 1e-9 * jn);  // sliding: the full Coulomb bound
    }
    if (mu == 5.0) {
      // Sticking: the contact point's tangential velocity is brought to zero.
      const Vec3 v = w.states[0].P / m, omega = s->inertiaBodyInv * w.states[0].L;
      EXPECT_NEAR((v + omega.cross(c.point)).x(), 0, 1e-9);
    }
  }
}

TEST(Impulse, SeparatingContactGetsNoImpulse) {
  auto s = test::boxShape(0.2, 0.2, 0.2, 800, 2);
  OneBody w(s);
  w.states[0].P = Vec3(0, 0, 1.0);
  Contact c;
  c.a = 0;
  c.point = Vec3(0, 0, -0.1);
  SolverSettings settings;
  settings.dt = 0.01;
  ContactCache cache;
  solveContacts({c}, w.bodies, w.states, settings, cache);
  EXPECT_EQ(w.states[0].P, Vec3(0, 0, 1.0));
  EXPECT_EQ(w.states[0].L, Vec3::Zero());
}

TEST(Impulse, WarmStartScalesLastStepsImpulseDownButNeverUp) {
  // A box resting on one contact under its centre: the contact carries m g dt per step.
  auto s = test::boxShape(0.2, 0.2, 0.2, 800, 2);
  const double m = s->mass, g = 9.81;
  OneBody w(s);
  Contact c;
  c.a = 0;
  c.point = Vec3(0, 0, -0.1);
  SolverSettings settings;
  settings.restingSpeed = 1.0;  // no bounce
  ContactCache cache;
  settings.dt = 0.02;
  w.states[0].P = Vec3(0, 0, -m * g * 0.02);  // gravity of one step
  solveContacts({c}, w.bodies, w.states, settings, cache);
  ASSERT_EQ(cache.impulses.size(), 1u);
  EXPECT_NEAR(cache.impulses[0].normal, m * g * 0.02, 1e-12 * m);
  // Half the step: the warm start alone (no passes) is m g 0.02 * (0.01 / 0.02), which exactly
  // cancels this step's gravity.
  settings.dt = 0.01;
  settings.iterations = 0;
  w.states[0].P = Vec3(0, 0, -m * g * 0.01);
  solveContacts({c}, w.bodies, w.states, settings, cache);
  EXPECT_NEAR(w.states[0].P.z(), 0, 1e-12 * m);
  // A sliver step (1e-12 s) whose impulse mostly corrects a 1e-4 m/s velocity error, then a
  // normal step: the warm start is never scaled up by the step ratio (1e10 here), so it stays
  // below what this step needs.
  settings.iterations = 12;
  settings.dt = 1e-12;
  w.states[0].P = Vec3(0, 0, -m * 1e-4);
  solveContacts({c}, w.bodies, w.states, settings, cache);
  settings.dt = 0.01;
  settings.iterations = 0;
  w.states[0].P = Vec3(0, 0, -m * g * 0.01);
  solveContacts({c}, w.bodies, w.states, settings, cache);
  EXPECT_LE(w.states[0].P.z(), 0.0);
  EXPECT_GE(w.states[0].P.z(), -m * g * 0.01);
}

// Patch blocks (SolverSettings::patchBlocks, used with contact reduction). A box falling flat
// onto three corners of its bottom face: the exact answer is a rebound at eps times the fall
// speed without spin, the two corners on the diagonal through the centre of mass carrying the
// whole impulse and the third none. With the block one pass gives it, to rounding (1e-10 of
// speeds of order 1 m/s); the point rows alone leave the box spinning after one pass (checked,
// so that the test shows what the block does).
TEST(Impulse, PatchBlockLandsABoxFlatOnThreeCornersInOnePass) {
  auto s = test::boxShape(0.4, 0.3, 0.2, 800, 2);
  const double m = s->mass, vz = -2.0, eps = 0.3;
  const std::vector<Vec3> corners = {Vec3(-0.2, -0.15, -0.1), Vec3(0.2, 0.15, -0.1),
                                     Vec3(0.2, -0.15, -0.1)};
  std::vector<Contact> contacts;
  for (std::size_t i = 0; i < corners.size(); ++i) {
    Contact c;
    c.a = 0;
    c.b = kGround;
    c.point = corners[i];
    c.normal = Vec3::UnitZ();
    c.leafA = static_cast<std::uint32_t>(i);
    contacts.push_back(c);
  }
  for (const bool blocks : {true, false}) {
    OneBody w(s);
    w.states[0].P = Vec3(0, 0, m * vz);
    SolverSettings settings;
    settings.dt = 0.01;
    settings.material.restitutionBodyGround = eps;
    settings.material.frictionBodyGround = 0.5;
    settings.iterations = 1;
    settings.patchBlocks = blocks;
    ContactCache cache;
    std::vector<double> jn;
    settings.normalImpulses = &jn;
    solveContacts(contacts, w.bodies, w.states, settings, cache);
    const Vec3 v = w.states[0].P / m;
    const Vec3 omega = s->inertiaBodyInv * w.states[0].L;
    if (!blocks) {
      EXPECT_GT(omega.norm(), 0.1) << "one pass of point rows alone should leave spin";
      continue;
    }
    EXPECT_NEAR(v.z(), -eps * vz, 1e-10);
    EXPECT_NEAR(omega.norm(), 0, 1e-10);
    for (const Vec3& r : corners) EXPECT_NEAR((v + omega.cross(r)).z(), -eps * vz, 1e-10);
    ASSERT_EQ(jn.size(), 3u);
    EXPECT_NEAR(jn[0], jn[1], 1e-10 * m);  // the diagonal's two corners share it equally
    EXPECT_NEAR(jn[2], 0.0, 1e-10 * m);    // the third corner: nothing, to rounding
  }
}

// patchBlockInverse against the definition of the pseudo-inverse: X is K^+ exactly when
// K X K = K, X K X = X and K X, X K are symmetric (the Penrose conditions). K is built here
// from its definition (1/M_a + 1/M_b + (r_ai x n).I_a^-1 (r_aj x n) + the same for b), for
// points in a plane through random lever arms, random inertias, a second body or none. The
// closed form is taken at a condition number of at most 1e6, so its rounding is at most about
// 1e6 x 2.2e-16 of K^+'s size; the conditions are asked to 1e-8 (relative), 50x that, which a
// missing null-direction term (a violation of order 1) or a wrong null vector fails (both
// checked). The eigen-decomposition's rounding is of the same order on these cases (the random
// quads reach condition numbers of a few thousand). Cases:
// well-spread patches of 2, 3 and 4 points (the closed form must be taken for the square,
// where the plane patches of a box on the floor are), and points on a line, where K loses a
// further rank and the eigen-decomposition must be taken and still give K^+.
Mat3 randomInverseInertia(Prng& rng) {
  const Quat q =
      Quat(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1))
          .normalized();
  const Vec3 moments(rng.uniform(0.2, 5), rng.uniform(0.2, 5), rng.uniform(0.2, 5));
  return q.toRotationMatrix() * moments.cwiseInverse().asDiagonal() *
         q.toRotationMatrix().transpose();
}

TEST(Impulse, PatchBlockInverseIsThePseudoInverse) {
  Prng rng(41);
  enum Way { kClosed, kEigen, kEither };
  auto check = [&](const std::vector<Vec3>& planar, Way way, bool twoBodies) {
    const int m = static_cast<int>(planar.size());
    const Vec3 n = Vec3(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1)).normalized();
    const Vec3 e1 = n.unitOrthogonal(), e2 = n.cross(e1);
    const Vec3 xa(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1));
    const Vec3 xb = xa + 0.8 * n + Vec3(rng.uniform(-0.3, 0.3), rng.uniform(-0.3, 0.3), 0);
    const double invMa = 1 / rng.uniform(1, 50), invMb = twoBodies ? 1 / rng.uniform(1, 50) : 0;
    const Mat3 Ia = randomInverseInertia(rng), Ib = twoBodies ? randomInverseInertia(rng) : Mat3();
    const Vec3 centre = xa - 0.3 * n;
    std::vector<Vec3> arm(m), armB(m);
    for (int i = 0; i < m; ++i) {
      const Vec3 point = centre + planar[i].x() * e1 + planar[i].y() * e2;
      arm[i] = (point - xa).cross(n);
      armB[i] = (point - xb).cross(n);
    }
    Eigen::Matrix4d K = Eigen::Matrix4d::Zero();
    for (int i = 0; i < m; ++i)
      for (int j = 0; j < m; ++j) {
        K(i, j) = invMa + invMb + arm[i].dot(Ia * arm[j]);
        if (twoBodies) K(i, j) += armB[i].dot(Ib * armB[j]);
      }
    Eigen::Matrix4d X;
    const bool usedClosed = patchBlockInverse(K, m, arm.data(), n, X);
    if (way == kClosed) {
      EXPECT_TRUE(usedClosed) << m << " points";
    }
    if (way == kEigen) {
      EXPECT_FALSE(usedClosed) << m << " points on a line";
    }
    const Eigen::MatrixXd k = K.topLeftCorner(m, m), x = X.topLeftCorner(m, m);
    const double tol = 1e-8;
    EXPECT_LT((k * x * k - k).norm(), tol * k.norm()) << m;
    EXPECT_LT((x * k * x - x).norm(), tol * x.norm()) << m;
    EXPECT_LT((k * x - (k * x).transpose()).norm(), tol * (k * x).norm()) << m;
    EXPECT_LT((x * k - (x * k).transpose()).norm(), tol * (x * k).norm()) << m;
  };
  for (const bool twoBodies : {false, true}) {
    for (int trial = 0; trial < 50; ++trial) {
      const double w = rng.uniform(0.1, 0.5), h = rng.uniform(0.1, 0.5);
      check({{-w, -h, 0}, {w, -h, 0}, {w, h, 0}, {-w, h, 0}}, kClosed, twoBodies);  // a face
      check({{-w, -h, 0}, {w, h, 0}}, kClosed, twoBodies);
      check({{-w, -h, 0}, {w, -h, 0}, {0, h, 0}}, kClosed, twoBodies);
      std::vector<Vec3> quad;  // any four points of a patch: either way, the conditions hold
      for (int i = 0; i < 4; ++i) quad.emplace_back(rng.uniform(-w, w), rng.uniform(-h, h), 0);
      check(quad, kEither, twoBodies);
      const Vec3 dir(rng.uniform(-1, 1), rng.uniform(-1, 1), 0);
      check({-w * dir, -0.3 * w * dir, 0.5 * w * dir, w * dir}, kEigen, twoBodies);
      check({-w * dir, 0.2 * w * dir, w * dir}, kEigen, twoBodies);
    }
  }
}

// Where the point rows alone converge, so do the blocks, to the same velocities: the
// frictionless contact problem has one solution in velocities (K is positive semidefinite),
// though four coplanar points can share their impulses in many ways. A box on its four bottom
// corners, falling at 1 m/s and rolling about x at w rad/s, so that the corners at -y approach
// at 1 + 0.15 w m/s and those at +y move at 0.15 w - 1: at 10 rad/s the block keeps every
// impulse >= 0 and is used in every pass (the +y corners end pressed to rest); at 30 rad/s it
// would pull on the separating +y corners in every pass, so the point rows alone do the work
// (both seen by counting the block's uses while writing this test). After 400 passes, with
// and without blocks, the same velocity and spin to 1e-9 (both converged: a further 400
// passes change neither by 1e-12).
TEST(Impulse, PatchBlocksConvergeToTheSameVelocitiesAsThePointRows) {
  auto s = test::boxShape(0.4, 0.3, 0.2, 800, 2);
  const double m = s->mass, eps = 0.3;
  std::vector<Contact> contacts;
  for (const double x : {-0.2, 0.2})
    for (const double y : {-0.15, 0.15}) {
      Contact c;
      c.a = 0;
      c.b = kGround;
      c.point = Vec3(x, y, -0.1);
      c.normal = Vec3::UnitZ();
      c.leafA = static_cast<std::uint32_t>(contacts.size());
      contacts.push_back(c);
    }
  for (const double spin : {10.0, 30.0}) {
    auto solve = [&](bool blocks, int passes) {
      OneBody w(s);
      w.states[0].P = Vec3(0, 0, -m);
      w.states[0].L = s->inertiaBodyInv.inverse() * Vec3(spin, 0, 0);
      SolverSettings settings;
      settings.dt = 0.01;
      settings.material.restitutionBodyGround = eps;
      settings.material.frictionBodyGround = 0;
      settings.iterations = passes;
      settings.stopWhenConverged = false;
      settings.patchBlocks = blocks;
      ContactCache cache;
      solveContacts(contacts, w.bodies, w.states, settings, cache);
      return std::pair<Vec3, Vec3>(w.states[0].P / m, s->inertiaBodyInv * w.states[0].L);
    };
    for (const bool blocks : {false, true}) {
      const auto [v400, w400] = solve(blocks, 400);
      const auto [v800, w800] = solve(blocks, 800);
      EXPECT_LT((v800 - v400).norm() + (w800 - w400).norm(), 1e-12) << "not converged";
    }
    const auto [vRows, wRows] = solve(false, 400);
    const auto [vBlocks, wBlocks] = solve(true, 400);
    EXPECT_LT((vRows - vBlocks).norm(), 1e-9) << spin << " rad/s";
    EXPECT_LT((wRows - wBlocks).norm(), 1e-9) << spin << " rad/s";
    // The corners at -y end at their targets (eps times their approach speed); those at +y,
    // which did not approach (target 0), are not pulled: at or above zero (to rounding).
    for (const Contact& c : contacts) {
      const double vn = (vBlocks + wBlocks.cross(c.point)).z();
      if (c.point.y() < 0)
        EXPECT_NEAR(vn, eps * (1 + 0.15 * spin), 1e-9) << spin << " rad/s";
      else
        EXPECT_GE(vn, -1e-12) << spin << " rad/s";
    }
  }
}

// The solver stops at the first pass that changes no accumulated impulse. Claim: the result is
// bit for bit that of all `iterations` passes. Two tilted boxes, one resting on the other on the
// floor (reduced contacts, as contact reduction leaves them: 4 per patch; 48 passes without
// patch blocks: with them the passes seldom reach a pass that changes no bit, so this is the
// case that shows the stop), solved step after step with gravity's
// impulse added and warm starting, as World does, with and without the stop: the same momenta in
// every bit, and the stop must have saved passes (or the comparison would show nothing).
TEST(Impulse, StoppingAtAPassThatChangesNothingGivesTheSameBits) {
  const TiltedBox box;
  const auto& s = box.shape;
  const double z0 = box.z0;
  const Quat q = box.q;
  struct Run {
    std::vector<BodyInfo> bodies;
    std::vector<BodyState> states;
    ContactCache cache;
    std::vector<double> jn;
    int passes = 0;
  };
  Run stop, full;
  for (Run* r : {&stop, &full}) {
    for (int i = 0; i < 2; ++i) {
      r->bodies.push_back(bodyOf(s));
      BodyState y;
      y.x = Vec3(0.03 * i, 0, z0 + i * (0.2 - 0.004));
      y.q = q;
      r->states.push_back(y);
    }
  }
  const double dt = 1e-3;
  int savedSteps = 0;
  for (int step = 0; step < 60; ++step) {
    for (Run* r : {&stop, &full}) {
      std::vector<Contact> contacts;
      const Collider a = sphereTreeCollider(0, *s->tree, r->states[0].x, r->states[0].q);
      const Collider b = sphereTreeCollider(1, *s->tree, r->states[1].x, r->states[1].q);
      collide(a, planeCollider(0.0), contacts);
      collide(a, b, contacts);
      ASSERT_GT(contacts.size(), 20u);
      reduceContacts(contacts);  // with leaf contacts 48 passes never reach a fixed point
      for (BodyState& y : r->states) y.P.z() -= s->mass * 9.81 * dt;
      SolverSettings settings;
      settings.iterations = 48;
      settings.restingSpeed = 9.81 * dt * 2;
      settings.dt = dt;
      settings.stopWhenConverged = r == &stop;
      settings.passes = &r->passes;
      settings.normalImpulses = &r->jn;
      solveContacts(contacts, r->bodies, r->states, settings, r->cache);
    }
    EXPECT_EQ(full.passes, 48);
    savedSteps += stop.passes < full.passes;
    for (int i = 0; i < 2; ++i) {  // bits, so that even the sign of a zero counts
      EXPECT_EQ(std::memcmp(stop.states[i].P.data(), full.states[i].P.data(), sizeof(Vec3)), 0)
          << "step " << step << ", body " << i;
      EXPECT_EQ(std::memcmp(stop.states[i].L.data(), full.states[i].L.data(), sizeof(Vec3)), 0)
          << "step " << step << ", body " << i;
    }
    ASSERT_EQ(stop.jn.size(), full.jn.size());
    EXPECT_EQ(std::memcmp(stop.jn.data(), full.jn.data(), stop.jn.size() * sizeof(double)), 0);
  }
  EXPECT_GT(savedSteps, 0) << "the stop never came early: the test compared nothing";
}

// Islands (sim/solve/islands.h) share no moving body, so the solver solves each on its own, on
// any thread. Independent check: three islands (two pairs of boxes side by side on the floor,
// each pair pressed together, and a single box, far apart, their contacts interleaved in the
// list; every box of a pair touches the floor and its neighbour) solved together on 1, 2 and 3
// threads, and each island's contacts solved alone, give the same momenta in every bit, step
// after step with warm starting, and the pass count of the whole is the largest island's.
TEST(Impulse, IslandsSolvedTogetherOnAnyThreadsOrAloneGiveTheSameBits) {
  const TiltedBox box;
  struct Run {
    std::vector<BodyInfo> bodies;
    std::vector<BodyState> states;
    std::vector<ContactCache> caches;  // one, or one per island
    int passes = 0;
  };
  // Bodies 0 and 1: a pair at x = 0; 2 and 3: a pair at x = 2; 4: alone at x = 4.
  const std::vector<std::vector<int>> islands = {{0, 1}, {2, 3}, {4}};
  auto makeRun = [&](int caches) {
    Run r;
    for (int i = 0; i < 5; ++i) {
      r.bodies.push_back(bodyOf(box.shape));
      BodyState y;
      const int second = i == 1 || i == 3;  // beside the first, 4 mm into it
      y.x = Vec3(2.0 * (i / 2) + second * (0.4 - 0.004), 0.01 * i, box.z0);
      y.q = box.q;
      y.L = Vec3(0.01 * i, -0.02, 0.005);
      r.states.push_back(y);
    }
    r.caches.resize(caches);
    return r;
  };
  std::vector<Run> together;
  for (int threads = 1; threads <= 3; ++threads) together.push_back(makeRun(1));
  Run alone = makeRun(3);
  const double dt = 1e-3;
  WorkerPool two(2), three(3);
  auto settingsFor = [&](int threads, int* passes) {
    SolverSettings settings;
    settings.restingSpeed = 9.81 * dt * 2;
    settings.dt = dt;
    settings.pool = threads == 3 ? &three : threads == 2 ? &two : nullptr;
    settings.passes = passes;
    return settings;
  };
  auto contactsOf = [&](const Run& r, const std::vector<int>& bodies) {
    // Ground contacts of every body first, then the pairs: the islands interleave.
    std::vector<Contact> contacts;
    auto tree = [&](int i) {
      return sphereTreeCollider(i, *box.shape->tree, r.states[i].x, r.states[i].q);
    };
    for (int i : bodies) collide(tree(i), planeCollider(0.0), contacts);
    for (int i : bodies)
      if (i % 2 == 0 && i + 1 < 5 && std::find(bodies.begin(), bodies.end(), i + 1) != bodies.end())
        collide(tree(i), tree(i + 1), contacts);
    return contacts;
  };
  for (int step = 0; step < 60; ++step) {
    for (Run* r : {&together[0], &together[1], &together[2], &alone})
      for (BodyState& y : r->states) y.P.z() -= box.shape->mass * 9.81 * dt;
    for (int t = 0; t < 3; ++t) {
      Run& r = together[t];
      const std::vector<Contact> contacts = contactsOf(r, {0, 1, 2, 3, 4});
      ASSERT_GE(contacts.size(), 64u) << "too few contacts for the solver to use threads";
      solveContacts(contacts, r.bodies, r.states, settingsFor(t + 1, &r.passes), r.caches[0]);
    }
    int largest = 0;
    for (std::size_t k = 0; k < islands.size(); ++k) {
      int passes = 0;
      solveContacts(contactsOf(alone, islands[k]), alone.bodies, alone.states,
                    settingsFor(1, &passes), alone.caches[k]);
      largest = std::max(largest, passes);
    }
    for (const Run& r : together) {
      EXPECT_EQ(r.passes, largest) << "step " << step;
      for (int i = 0; i < 5; ++i) {
        EXPECT_EQ(std::memcmp(r.states[i].P.data(), alone.states[i].P.data(), sizeof(Vec3)), 0)
            << "step " << step << ", body " << i;
        EXPECT_EQ(std::memcmp(r.states[i].L.data(), alone.states[i].L.data(), sizeof(Vec3)), 0)
            << "step " << step << ", body " << i;
      }
    }
  }
}

}  // namespace
}  // namespace vf

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
//     over steps. (Passes always run forward: alternating sweeps converge worse on a flat
//     landing.) The scale never exceeds 1 because part of an impulse
//     corrects velocity errors and does not grow with dt: after a very short step (a release
//     time just after a frame time), scaling up by the step ratio would blow bodies apart.
//     With the extensions a contact can also be seeded by a cached contact of another key
//     (contact reduction's representatives) or by one kept while its bodies slept
//     (contact_cache.cpp).
//   - with contact reduction (an extension, SolverSettings::patchBlocks), each pass first
//     solves the normal impulses of a patch of 2-4 points together ("patch blocks", below).
// A single new contact gets exactly eq. 15 in the first pass, and later passes change nothing.
#include "sim/solve/impulse.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <utility>

#include "sim/core/worker_pool.h"
#include "sim/ground/ground_material.h"
#include "sim/solve/islands.h"

namespace vf {

double inverseEffectiveMass(double invMassA, const Mat3& invInertiaA, const Vec3& ra,
                            double invMassB, const Mat3& invInertiaB, const Vec3& rb,
                            const Vec3& d) {
  // d . [(I1^-1 (r1 x d)) x r1] = (r1 x d) . I1^-1 (r1 x d): the paper's form, rearranged.
  const Vec3 raXd = ra.cross(d), rbXd = rb.cross(d);
  return invMassA + invMassB + raXd.dot(invInertiaA * raXd) + rbXd.dot(invInertiaB * rbXd);
}

namespace {

struct Motion {  // velocities during the solve
  Vec3 v = Vec3::Zero();
  Vec3 w = Vec3::Zero();
  Mat3 invI = Mat3::Zero();  // world frame: R I_body^-1 R^T
  double invMass = 0;
};

// One direction d of a contact (the normal or a tangent), prepared once per step so that a
// pass costs dot products and additions only: the relative velocity along d is
// d.(v_a - v_b) + (r_a x d).w_a - (r_b x d).w_b, and an impulse j d changes w_a by
// j I_a^-1 (r_a x d) and w_b by -j I_b^-1 (r_b x d).
struct Axis {
  Vec3 d;
  Vec3 raXd, rbXd;  // lever-arm cross products
  Vec3 dwA, dwB;    // I_a^-1 (r_a x d), I_b^-1 (r_b x d): spin per unit impulse
  double k = 0;     // effective mass 1 / (eq. 15's denominator)
};

struct Row {  // one contact, prepared
  ContactKey key;
  Vec3 point;    // the contact point (world), for the cache
  double reach;  // how far a cached point may lie to seed it (warmStartNearest), m
  int a, b;      // motion indices; b may be the ground slot
  Vec3 ra, rb;
  Axis n, t1, t2;
  double target;  // wanted normal velocity
  double mu;
  double jn = 0, jt1 = 0, jt2 = 0;  // accumulated impulses
  bool patch = false;               // first row of a patch: its block is patches[k], k its contact
  bool fixedB = false;              // b does not move: its island's zero slot (groupIslands)
};

// Rounding allowance of a patch block's impulses, relative to the largest (see solveIsland).
constexpr double kZeroShare = 1e-9;

// A patch block (SolverSettings::patchBlocks): the rows [first, first + count) of one body pair
// share the normal; `inverse` is the pseudo-inverse of their normal block K (count x count,
// top left), K_ij = the normal velocity at point i per unit normal impulse at point j.
struct Patch {
  Eigen::Matrix4d inverse;
  int count = 0;
};

// Two unit tangents completing n to a right-handed basis (fixed choice: deterministic).
void tangents(const Vec3& n, Vec3& t1, Vec3& t2) {
  const Vec3 helper = std::abs(n.x()) < 0.57 ? Vec3::UnitX() : Vec3::UnitY();
  t1 = n.cross(helper).normalized();
  t2 = n.cross(t1);
}

struct SolverScratch {
  std::vector<Motion> motion;
  std::vector<Row> rows;
  std::vector<Patch> patches;
  // rows[k] and patches[k] belong to contact k (most patches[k] unused: no clearing needed).
  std::vector<int> root, islandOfRoot, start, order, contactIsland, next, runStart, islandPasses;
  std::vector<char> made;  // made[k]: contact k has a row
  // claimed[i]: cache entry i has seeded a row (each seeds at most one). Islands share no body
  // pair, so the threads solving them write disjoint entries.
  std::vector<char> claimed;
  std::vector<char> warm;  // warm[k]: contact k's row was seeded from the cache
};

// Fewer rows than this are solved on one thread: waking a worker costs about as much as a few
// dozen rows' passes.
constexpr int kRowsPerThread = 64;
// Runs of islands per thread: enough that a thread whose runs were cheap takes more.
constexpr int kRunsPerThread = 8;

Vec3 pointVelocity(const Motion& m, const Vec3& r) { return m.v + m.w.cross(r); }

Axis makeAxis(const Vec3& d, const Vec3& ra, const Vec3& rb, const Motion& A, const Motion& B) {
  Axis x;
  x.d = d;
  x.raXd = ra.cross(d);
  x.rbXd = rb.cross(d);
  x.dwA = A.invI * x.raXd;
  x.dwB = B.invI * x.rbXd;
  // inverseEffectiveMass's expression on the products just made (the same operations in the
  // same order, so the same bits).
  x.k = 1.0 / (A.invMass + B.invMass + x.raXd.dot(x.dwA) + x.rbXd.dot(x.dwB));
  return x;
}

// Relative velocity of the contact point along the axis (body a minus body b).
//
// kFixedB: body b does not move (the ground, a static or sleeping body: its island's zero
// slot, groupIslands). Its slot's velocities stay +0 for good (every push subtracts a signed
// zero from +0, which gives +0), so d.(v_a - v_b) is d.v_a to the bit, and the term of w_b is
// a signed zero, which changes no non-zero sum; its terms are left out, and pushes leave the
// slot alone. (The checksums of every benchmark scene stayed the same.)
template <bool kFixedB = false>
double along(const Axis& x, const Motion& A, const Motion& B) {
  if constexpr (kFixedB) return x.d.dot(A.v) + x.raXd.dot(A.w);
  return x.d.dot(A.v - B.v) + x.raXd.dot(A.w) - x.rbXd.dot(B.w);
}

// Applies the impulse j along the axis: +j on body a, -j on body b. Always inlined: the passes
// call it up to five times a row.
template <bool kFixedB = false>
inline __attribute__((always_inline)) void push(const Axis& x, double j, Motion& A, Motion& B) {
  A.v += (j * A.invMass) * x.d;
  A.w += j * x.dwA;
  if constexpr (kFixedB) return;
  B.v -= (j * B.invMass) * x.d;
  B.w -= j * x.dwB;
}

// Each moving body's velocities and world inverse inertia; slot n (the floor) and the bodies
// that do not move stay zero.
void prepareMotion(const std::vector<BodyInfo>& bodies, const std::vector<BodyState>& states,
                   WorkerPool* pool, std::vector<Motion>& motion) {
  const int n = static_cast<int>(bodies.size());
  motion.resize(n + 1);
  motion[n] = Motion{};
  WorkerPool::forRanges(pool, n, WorkerPool::kBodiesPerRange, [&](int lo, int hi) {
    for (int i = lo; i < hi; ++i) {
      Motion& m = motion[i];
      if (!bodies[i].moves()) {
        m = Motion{};
        continue;
      }
      const BodyState& y = states[i];
      m.invMass = bodies[i].invMass;
      m.invI = inverseInertiaWorld(bodies[i], y);
      m.v = velocityOf(bodies[i], y);
      m.w = m.invI * y.L;
    }
  });
}

// Contact k's row: axes, material, restitution target, from the velocities before any
// impulse of the step. Sides that do not move (the ground, static and sleeping bodies) use the
// island's zero slot (groupIslands), whose motion is zero like theirs. False where the effective
// mass is not finite (both sides immovable, or a non-finite state): no row.
bool prepareRow(const std::vector<Contact>& contacts, int k, const std::vector<BodyInfo>& bodies,
                const std::vector<BodyState>& states, const SolverSettings& settings,
                const std::vector<Motion>& motion, int zeroSlot, Row& r) {
  const ContactMaterial& mat = settings.material;
  const Contact& c = contacts[static_cast<std::size_t>(k)];
  r.key = ContactKey{c.a, c.b, c.leafA, c.leafB};
  r.point = c.point;
  r.reach = settings.warmStartNearest
                ? representativeReach(bodies[c.a], c.b == kGround ? nullptr : &bodies[c.b])
                : 0.0;
  r.a = bodies[c.a].moves() ? c.a : zeroSlot;
  r.fixedB = c.b == kGround || !bodies[c.b].moves();
  r.b = r.fixedB ? zeroSlot : c.b;
  r.ra = c.point - states[c.a].x;
  r.rb = c.b == kGround ? Vec3::Zero() : Vec3(c.point - states[c.b].x);
  Vec3 t1, t2;
  tangents(c.normal, t1, t2);
  const Motion& A = motion[r.a];
  const Motion& B = motion[r.b];
  r.n = makeAxis(c.normal, r.ra, r.rb, A, B);
  if (!std::isfinite(r.n.k)) return false;  // a non-finite state (or nothing moves)
  r.t1 = makeAxis(t1, r.ra, r.rb, A, B);
  r.t2 = makeAxis(t2, r.ra, r.rb, A, B);
  const bool ground = c.b == kGround || bodies[c.a].isStatic || bodies[c.b].isStatic;
  double eps = ground ? mat.restitutionBodyGround : mat.restitutionBodyBody;
  r.mu = ground ? mat.frictionBodyGround : mat.frictionBodyBody;
  if (c.b == kGround && settings.ground) {  // rock fall: the material under the contact
    const GroundCoefficients m = settings.ground->coefficientsAt(c.point.x(), c.point.y());
    eps = m.restitution;
    r.mu = m.friction;
    if (m.law == GroundLawKind::kSlip) {  // mu(s) of the body's slippage (slip_law.cpp)
      const std::vector<double>* s = settings.slippage;
      r.mu = slipFriction(m, s && static_cast<std::size_t>(c.a) < s->size() ? (*s)[c.a] : 0.0);
    }
  }
  r.patch = false;
  r.jn = r.jt1 = r.jt2 = 0;
  const double vRel = c.normal.dot(pointVelocity(A, r.ra) - pointVelocity(B, r.rb));
  r.target = vRel < -settings.restingSpeed ? -eps * vRel : 0.0;  // v_rel+ = -eps v_rel-
  return true;
}

// Patch blocks, an extension for reduced contacts (the paper solves leaf contacts one by
// one). Gauss-Seidel converges slowly on the few points that hold a flat patch: the first
// point of a flat landing takes the whole impulse and tilts the body, and the others take it
// back over many passes (a box landing flat, three of its corner leaves touching first, is
// still tilted by 0.01 rad after 12 such passes). So, before the rows of a patch, its
// normal impulses are solved together, as Box2D's block solver does for its two-point
// manifolds: the increments dj with K dj = target - u (u the points' normal velocities now)
// in one step. On a patch of up to four points K has rank at most three (a rigid body has
// three motions that move points along one normal: the translation along it and the two
// rotations about axes in the plane), so four coplanar points are statically indeterminate
// and dj is taken with K's pseudo-inverse (the least-norm increment: evenly spread where the
// points are placed evenly; patchBlockInverse). The block is used only when every accumulated
// impulse stays >= 0; otherwise (a point must let go) the point rows alone do the pass. Every point
// at its target with every impulse >= 0 solves the contact problem, and for frictionless contacts
// all its solutions have the same velocities (K is positive semidefinite), so the blocks change how
// fast the passes get there, not where (impulse_test). Friction stays with the point rows. A patch:
// 2-4 consecutive rows of one body pair with bitwise the same normal (contact reduction gives a
// reduced patch's points one normal; plane contacts share the plane's).
// The patches among the rows first[0..count) of one island (contact order). Rows of one body
// pair are consecutive contacts (each collider pair's contacts come out together), so a patch
// is a run of consecutive contact indices with the same bodies and normal. (Consecutive rows
// would differ from that only where a contact without a row, from a non-finite state, lies
// between two contacts of one pair: no patch spans such a gap.)
void preparePatches(const std::vector<Contact>& contacts, const int* first, int count, Row* rows,
                    const Motion* motion, Patch* patches) {
  for (int f = 0; f < count;) {
    const Contact& head = contacts[static_cast<std::size_t>(first[f])];
    int e = f + 1;
    while (e < count && first[e] == first[e - 1] + 1) {
      const Contact& c = contacts[static_cast<std::size_t>(first[e])];
      if (c.a != head.a || c.b != head.b || c.normal != head.normal) break;
      ++e;
    }
    const int m = e - f;
    if (m >= 2 && m <= 4) {
      Row& r0 = rows[first[f]];
      const Motion& A = motion[r0.a];
      const Motion& B = motion[r0.b];
      Eigen::Matrix4d K = Eigen::Matrix4d::Zero();
      for (int i = 0; i < m; ++i)
        for (int j = 0; j < m; ++j) {
          const Axis& x = rows[first[f + i]].n;
          const Axis& y = rows[first[f + j]].n;
          K(i, j) = A.invMass + B.invMass + x.raXd.dot(y.dwA) + x.rbXd.dot(y.dwB);
        }
      Vec3 arms[4];
      for (int i = 0; i < m; ++i) arms[i] = rows[first[f + i]].n.raXd;
      Patch& p = patches[first[f]];
      patchBlockInverse(K, m, arms, head.normal, p.inverse);
      p.count = m;
      r0.patch = true;
    }
    f = e;
  }
}

// Islands (sim/solve/islands.h) share no moving body, and a contact changes the velocities of
// its own island only, so passes over all rows and passes over one island at a time give each
// body the same sequence of operations: the same bits. Each island is therefore solved on its
// own, on any thread, and stops at its own first pass that changes nothing (a pass over the
// whole set stops where the last island does, so `passes` is the largest island's count).
// The ground and bodies that do not move take no impulse: their motion stays zero, but every
// row still writes it, so each island gets a zero slot of its own (n + island) for them.
// Fills w.start (island i's contacts are w.order[start[i], start[i + 1])), w.order (contact
// indices, island by island, in contact order within each; the island's job moves those that
// get a row to the front of its range) and the zero slots; returns the island count. A contact
// of which neither side moves has no row and no island.
int groupIslands(const std::vector<Contact>& contacts, const std::vector<BodyInfo>& bodies,
                 SolverScratch& w) {
  const int n = static_cast<int>(bodies.size());
  const int count = static_cast<int>(contacts.size());
  std::vector<int>& start = w.start;  // contacts per island first, then offsets into `order`
  std::vector<int>& contactIsland = w.contactIsland;
  islandRoots(contacts, bodies, w.root);
  w.islandOfRoot.assign(n, -1);
  start.clear();
  contactIsland.resize(count);
  for (int k = 0; k < count; ++k) {
    const Contact& c = contacts[static_cast<std::size_t>(k)];
    const bool movesA = bodies[c.a].moves();
    if (!movesA && (c.b == kGround || !bodies[c.b].moves())) {
      contactIsland[k] = -1;
      continue;
    }
    int& island = w.islandOfRoot[w.root[movesA ? c.a : c.b]];
    if (island < 0) {
      island = static_cast<int>(start.size());
      start.push_back(0);
    }
    ++start[island];
    contactIsland[k] = island;
  }
  const int islands = static_cast<int>(start.size());
  w.motion.resize(n + islands);  // the zero slots (the ground's slot n is island 0's)
  int offset = 0;
  for (int& s : start) offset += std::exchange(s, offset);
  start.push_back(offset);
  w.order.resize(offset);
  w.next.assign(start.begin(), start.end() - 1);
  for (int k = 0; k < count; ++k)
    if (contactIsland[k] >= 0) w.order[w.next[contactIsland[k]]++] = k;  // contact order kept
  return islands;
}

// One pass over row *k (and, first, its patch's block when it starts one), as solveIsland
// describes; returns whether an accumulated impulse changed.
template <bool kFixedB>
bool passRow(const int* k, Row* rows, const Patch* patches, Motion& A, Motion& B) {
  Row& r = rows[*k];
  bool changed = false;
  if (r.patch) {  // the patch's block (preparePatches), before its point rows
    const Patch& p = patches[*k];
    double error[4], jn[4];
    for (int i = 0; i < p.count; ++i) {
      const Row& q = rows[k[i]];
      error[i] = q.target - along<kFixedB>(q.n, A, B);
    }
    // A point whose exact share is zero (a box landing on three corners: the two on a
    // diagonal through the centre of mass carry it all) comes out at -1e-14 or so: a
    // share below zero by less than kZeroShare of the largest is rounding, set to zero.
    double largest = 0;
    for (int i = 0; i < p.count; ++i) {
      double dj = 0;
      for (int l = 0; l < p.count; ++l) dj += p.inverse(i, l) * error[l];
      jn[i] = rows[k[i]].jn + dj;
      largest = std::max(largest, jn[i]);
    }
    bool pushes = true;  // no accumulated impulse below zero
    for (int i = 0; i < p.count; ++i) {
      if (jn[i] < 0.0 && jn[i] >= -kZeroShare * largest) jn[i] = 0.0;
      pushes = pushes && jn[i] >= 0.0;
    }
    for (int i = 0; pushes && i < p.count; ++i) {
      Row& q = rows[k[i]];
      if (jn[i] == q.jn) continue;
      push<kFixedB>(q.n, jn[i] - q.jn, A, B);
      q.jn = jn[i];
      changed = true;
    }
  }
  // Normal: eq. 15 towards the target, accumulated impulse kept >= 0.
  const double vn = along<kFixedB>(r.n, A, B);
  const double jn = std::max(r.jn + (r.target - vn) * r.n.k, 0.0);
  const double djn = jn - r.jn;
  r.jn = jn;
  if (djn != 0.0) push<kFixedB>(r.n, djn, A, B);
  // Friction: stop the tangential slip, within the Coulomb disc of the current jn.
  double jt1 = r.jt1 - along<kFixedB>(r.t1, A, B) * r.t1.k;
  double jt2 = r.jt2 - along<kFixedB>(r.t2, A, B) * r.t2.k;
  const double limit = r.mu * r.jn;
  const double jt = std::sqrt(jt1 * jt1 + jt2 * jt2);
  if (jt > limit) {
    const double s = limit / jt;
    jt1 *= s;
    jt2 *= s;
  }
  push<kFixedB>(r.t1, jt1 - r.jt1, A, B);
  push<kFixedB>(r.t2, jt2 - r.jt2, A, B);
  changed = changed || djn != 0.0 || jt1 != r.jt1 || jt2 != r.jt2;
  r.jt1 = jt1;
  r.jt2 = jt2;
  return changed;
}

// Seeds row r from cache entry e (an impulse of the same contact, or with `reproject` one
// standing for it, whose normal and tangents may differ from r's: its world vector is taken
// along r's axes, the normal part kept >= 0) and applies that impulse.
void seedRow(Row& r, const CachedImpulse& e, bool reproject, double dt, Motion* motion) {
  const double scale = warmStartScale(e, dt);
  if (reproject) {
    r.jn = std::max(0.0, e.impulse.dot(r.n.d)) * scale;
    r.jt1 = e.impulse.dot(r.t1.d) * scale;
    r.jt2 = e.impulse.dot(r.t2.d) * scale;
  } else {
    r.jn = e.normal * scale;
    r.jt1 = e.tangent1 * scale;
    r.jt2 = e.tangent2 * scale;
  }
  push(r.n, r.jn, motion[r.a], motion[r.b]);
  push(r.t1, r.jt1, motion[r.a], motion[r.b]);
  push(r.t2, r.jt2, motion[r.a], motion[r.b]);
}

// Warm start of the rows [first, last) of one island (contact_cache.h): every row whose contact
// the cache holds by key, then, with warmStartNearest, the rest from the nearest unclaimed
// entry of their body pair, in row order.
void warmStart(const int* first, const int* last, Row* rows, Motion* motion,
               const ContactCache& cache, SolverScratch& w, const SolverSettings& settings) {
  for (const int* k = first; k != last; ++k) {
    Row& r = rows[*k];
    const std::ptrdiff_t e = findCached(cache, r.key);
    if (e < 0) continue;
    w.claimed[static_cast<std::size_t>(e)] = 1;
    w.warm[static_cast<std::size_t>(*k)] = 1;
    seedRow(r, cache.impulses[static_cast<std::size_t>(e)], false, settings.dt, motion);
  }
  if (!settings.warmStartNearest) return;
  for (const int* k = first; k != last; ++k) {
    Row& r = rows[*k];
    if (w.warm[static_cast<std::size_t>(*k)]) continue;
    const std::ptrdiff_t e = nearestCached(cache, r.key.a, r.key.b, r.point, r.reach, w.claimed);
    if (e < 0) continue;
    w.claimed[static_cast<std::size_t>(e)] = 1;
    w.warm[static_cast<std::size_t>(*k)] = 1;
    seedRow(r, cache.impulses[static_cast<std::size_t>(e)], true, settings.dt, motion);
  }
}

// Warm start and passes over the rows [first, last) of one island; returns the passes made.
int solveIsland(const int* first, const int* last, Row* rows, const Patch* patches, Motion* motion,
                const ContactCache& cache, SolverScratch& w, const SolverSettings& settings) {
  warmStart(first, last, rows, motion, cache, w, settings);
  // A pass that changes no accumulated impulse leaves every velocity as it was (it pushes only
  // zero impulses), so every later pass would repeat it: the passes stop there, with the
  // result of all `iterations` passes (tests/sim/impulse_test.cpp compares both).
  int pass = 0;
  while (pass < settings.iterations) {
    ++pass;
    bool changed = false;
    for (const int* k = first; k != last; ++k) {
      const Row& r = rows[*k];
      Motion& A = motion[r.a];
      Motion& B = motion[r.b];
      changed = (r.fixedB ? passRow<true>(k, rows, patches, A, B)
                          : passRow<false>(k, rows, patches, A, B)) ||
                changed;
    }
    if (!changed && settings.stopWhenConverged) break;
  }
  return pass;
}

// Prepares and solves every island, on the pool's threads when there is enough to share;
// returns the largest island's pass count. An island's rows and patches are prepared by the
// thread that then solves them (prepared by one thread and solved by another, every row's
// cache lines cross cores twice a step: 1,000 rocks on 2 threads spend longer preparing rows
// than on 1). Which thread takes an island changes nothing: its rows are a function of its
// contacts and of its bodies' motions, which no other island touches.
int solveIslands(int islands, const std::vector<Contact>& contacts,
                 const std::vector<BodyInfo>& bodies, const std::vector<BodyState>& states,
                 SolverScratch& w, const ContactCache& cache, const SolverSettings& settings) {
  const int n = static_cast<int>(bodies.size());
  const int count = w.start[islands];
  auto solve = [&](int i) {
    int* order = w.order.data();
    int end = w.start[i];                              // the rows made so far: order[start[i], end)
    for (int p = w.start[i]; p < w.start[i + 1]; ++p)  // rows that exist, in contact order
      if (prepareRow(contacts, order[p], bodies, states, settings, w.motion, n + i,
                     w.rows[static_cast<std::size_t>(order[p])])) {
        w.made[static_cast<std::size_t>(order[p])] = 1;
        order[end++] = order[p];
      }
    if (end == w.start[i]) return 0;
    if (settings.patchBlocks)
      preparePatches(contacts, order + w.start[i], end - w.start[i], w.rows.data(), w.motion.data(),
                     w.patches.data());
    return solveIsland(order + w.start[i], order + end, w.rows.data(), w.patches.data(),
                       w.motion.data(), cache, w, settings);
  };
  const int threads = islands < 2 || count < kRowsPerThread || !settings.pool
                          ? 1
                          : std::min(settings.pool->threads(), islands);
  std::vector<int>& islandPasses = w.islandPasses;
  islandPasses.assign(islands, 0);
  if (threads == 1) {
    for (int i = 0; i < islands; ++i) islandPasses[i] = solve(i);
  } else {
    // Runs of consecutive islands with about equal numbers of contacts: neighbouring islands often
    // lie side by side in memory (their bodies' ids are close), and threads solving them at
    // once slow each other down (one island at a time: no gain over one thread on 1,000
    // rocks).
    std::vector<int>& runStart = w.runStart;
    runStart.assign(1, 0);
    const int runs = threads * kRunsPerThread;
    for (int i = 1; i < islands; ++i)
      if (static_cast<std::int64_t>(w.start[i]) * runs >=
          static_cast<std::int64_t>(runStart.size()) * count)
        runStart.push_back(i);
    runStart.push_back(islands);
    settings.pool->run(static_cast<int>(runStart.size()) - 1, [&](int k) {
      for (int i = runStart[k]; i < runStart[k + 1]; ++i) islandPasses[i] = solve(i);
    });
  }
  return islands ? *std::max_element(islandPasses.begin(), islandPasses.end()) : 0;
}

// P1 += J, L1 += r1 x J for the total impulse of every row (and the opposite on body 2), in
// contact order.
void applyImpulses(const SolverScratch& w, const std::vector<BodyInfo>& bodies,
                   std::vector<BodyState>& states) {
  const int n = static_cast<int>(bodies.size());
  for (int k = 0; k < static_cast<int>(w.made.size()); ++k) {
    if (!w.made[static_cast<std::size_t>(k)]) continue;
    const Row& r = w.rows[static_cast<std::size_t>(k)];
    const Vec3 J = r.jn * r.n.d + r.jt1 * r.t1.d + r.jt2 * r.t2.d;
    if (r.a < n) {
      states[r.a].P += J;
      states[r.a].L += r.ra.cross(J);
    }
    if (!r.fixedB) {
      states[r.b].P -= J;
      states[r.b].L -= r.rb.cross(J);
    }
  }
}

}  // namespace

void solveContacts(const std::vector<Contact>& contacts, const std::vector<BodyInfo>& bodies,
                   std::vector<BodyState>& states, const SolverSettings& settings,
                   ContactCache& cache) {
  // The next step's cache: this step's resting contacts and the sleeping bodies' (kept first,
  // while the previous cache is still whole).
  std::vector<CachedImpulse>& next = cache.scratch;
  next.clear();
  keepSleepingContacts(cache, bodies, next);
  if (contacts.empty()) {
    if (settings.passes) *settings.passes = 0;
    if (settings.normalImpulses) settings.normalImpulses->clear();
    cache.impulses.swap(next);
    return;
  }
  // Scratch reused from step to step (per thread: ensembles step worlds on several). Passed on
  // by reference: in code that other threads run, the name of a thread_local would denote that
  // thread's own (empty) copy.
  static thread_local SolverScratch scratch;
  SolverScratch& w = scratch;
  prepareMotion(bodies, states, settings.pool, w.motion);
  const int islands = groupIslands(contacts, bodies, w);
  w.rows.resize(contacts.size());
  if (settings.patchBlocks) w.patches.resize(contacts.size());
  w.made.assign(contacts.size(), 0);
  w.warm.assign(contacts.size(), 0);
  w.claimed.assign(cache.impulses.size(), 0);
  const int passes = solveIslands(islands, contacts, bodies, states, w, cache, settings);
  if (settings.passes) *settings.passes = passes;

  // Only resting contacts seed the next step: an impact's impulse belongs to its own step, and
  // re-applied while the bodies separate it would throw them apart.
  for (std::size_t k = 0; k < contacts.size(); ++k) {
    const Row& r = w.rows[k];
    if (!w.made[k] || r.target != 0.0) continue;
    const Vec3 impulse = r.jn * r.n.d + r.jt1 * r.t1.d + r.jt2 * r.t2.d;
    next.push_back({r.key, r.jn, r.jt1, r.jt2, impulse, r.point, settings.dt});
  }
  std::sort(next.begin(), next.end(),
            [](const CachedImpulse& x, const CachedImpulse& y) { return x.key < y.key; });
  cache.impulses.swap(next);

  if (settings.normalImpulses) {
    settings.normalImpulses->assign(contacts.size(), 0.0);
    for (std::size_t k = 0; k < contacts.size(); ++k)
      if (w.made[k]) (*settings.normalImpulses)[k] = w.rows[k].jn;
  }
  applyImpulses(w, bodies, states);
}

}  // namespace vf

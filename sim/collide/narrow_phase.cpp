// The hierarchical sphere-tree test of fig. 3, and its plane variant.
//
// Body-body: bounding spheres first (the sphere circumscribing the body, not the larger
// level-0 voxel sphere), then every level-1 sphere of A against every level-1 sphere of B,
// then, for each colliding pair only, the children pairs at the next level, down to the leaf
// level Lv, where a colliding pair is a contact. When the two trees have different leaf levels
// (a shape may override the scene's level) the one already at its leaves stops descending and
// the other goes on alone.
//
// Because each voxel's circumscribed sphere contains its children's spheres, this finds exactly
// the leaf pairs that a test of all leaf spheres against all leaf spheres finds
// (tests/sim/narrow_phase_test.cpp checks that against brute force on random poses). In
// floating point "contains" holds only up to rounding: a box's corner leaf touches every
// ancestor's sphere at the corner, so a pruning test that rounds differently from the leaf test
// could drop a leaf pair that touches. The pruning tests (bounding spheres, inner nodes) are
// therefore widened by roundingSlack (contact.h), and only leaf tests decide; the test file
// checks exactly such corner contacts, tens of km from the origin.
//
// Centres are computed once per visited node and passed down, so each sphere test is one
// squared distance.
#include "sim/collide/narrow_phase.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <type_traits>
#include <utility>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "sim/collide/contact_reduction.h"
#include "sim/collide/polygon_contact.h"
#include "sim/core/error.h"
#include "sim/core/worker_pool.h"
#include "sim/geometry/mesh_bvh.h"
#include "sim/shape/convex_polyhedron.h"

namespace vf {
namespace {

// Temporal coherence (PairCandidates): candidates are kept within kCandidateMargin of the two
// leaf radii beyond touching, and built only after a step in which the pair moved less than
// kCalmStep of that margin, so that they are likely to serve several steps (a tumbling pair
// would rebuild them every step, at more than a plain descent's cost).
constexpr double kCandidateMargin = 0.25;
constexpr double kCalmStep = 0.25;

// What a pair's test does this time (PairCandidates): test only the stored candidates, build new
// ones while descending, or descend plainly. `sinceBuild` and `sinceLast` bound how far any leaf
// centre moved relative to the other side since the candidates' pose and since the last test's
// (infinity where there is none); `slack` is the pair's rounding slack.
enum class CandidatePlan { kServe, kBuild, kDescend };
CandidatePlan chooseCandidatePlan(const PairCandidates& m, double sinceBuild, double sinceLast,
                                  double margin, double slack) {
  if (m.holds && sinceBuild < m.margin - 2 * slack) return CandidatePlan::kServe;
  return sinceLast < kCalmStep * margin ? CandidatePlan::kBuild : CandidatePlan::kDescend;
}

// A node of a sphere tree met by descendAlone and the terrain descent.
struct NodeRef {
  int level;
  std::uint32_t index;
  Vec3 center;  // world
};

// World centre of leaf i of a sphere-tree collider, by the expression the world-frame descent
// (descendAlone) uses, so that every place that tests a leaf on its own gets the same bits (a
// one-level tree's root leaf stands at the body origin). Always inlined: GCC leaves it a call in
// the leaf loops, and inlining it takes a Lv 6 crosses run from 1,450 to 1,320 ms (3 interleaved
// runs each).
inline __attribute__((always_inline)) Vec3 leafWorldCenter(const Collider& c, std::uint32_t i) {
  const SphereTree& tree = *c.tree;
  return tree.leafLevel() == 0 ? c.x : Vec3(c.x + c.R * tree.leaves().centers[i]);
}

// Height of the point c above plane collider p, by the one expression every plane test uses
// (the descent, its candidates and the reduction from them must agree to the bit).
inline double planeHeight(const Collider& p, const Vec3& c) { return p.normal.dot(c) - p.offset; }

// A point of body a's frame in single precision, and up to 8 of them as structure of arrays
// (a node has at most 8 children), for the tree-tree descent's pruning tests.
struct Point3f {
  float x, y, z;
};
constexpr int kLanes = 8;
struct alignas(32) Lanes {
  float x[kLanes], y[kLanes], z[kLanes];
  Point3f operator[](int k) const { return {x[k], y[k], z[k]}; }
  static Lanes single(const Point3f& p) {  // p in lane 0, the other lanes defined (zero)
    Lanes s{};
    s.x[0] = p.x, s.y[0] = p.y, s.z[0] = p.z;
    return s;
  }
};

// Bit k (k < 4) set where point k of (x, y, z) lies closer than sqrt(r2) to p. GCC does not
// vectorise the plain loop (it builds the mask bit by bit), so on x86-64 it is written with
// SSE, which every x86-64 has; elsewhere the loop, which gives the same bits.
inline unsigned closerThan4(const float* x, const float* y, const float* z, const Point3f& p,
                            float r2) {
#if defined(__SSE2__)
  const __m128 dx = _mm_sub_ps(_mm_loadu_ps(x), _mm_set1_ps(p.x));
  const __m128 dy = _mm_sub_ps(_mm_loadu_ps(y), _mm_set1_ps(p.y));
  const __m128 dz = _mm_sub_ps(_mm_loadu_ps(z), _mm_set1_ps(p.z));
  const __m128 d2 =
      _mm_add_ps(_mm_add_ps(_mm_mul_ps(dx, dx), _mm_mul_ps(dy, dy)), _mm_mul_ps(dz, dz));
  return static_cast<unsigned>(_mm_movemask_ps(_mm_cmplt_ps(d2, _mm_set1_ps(r2))));
#else
  unsigned mask = 0;
  for (int k = 0; k < 4; ++k) {
    const float dx = x[k] - p.x, dy = y[k] - p.y, dz = z[k] - p.z;
    mask |= static_cast<unsigned>(dx * dx + dy * dy + dz * dz < r2) << k;
  }
  return mask;
#endif
}

// The set bits of an 8-bit mask. (__builtin_popcount is a libgcc call on x86-64 without the
// POPCNT instruction, which the baseline lacks: 1.9 % of a stack run, perf.)
constexpr int bits8(unsigned m) {
  m = m - ((m >> 1) & 0x55u);
  m = (m & 0x33u) + ((m >> 2) & 0x33u);
  return static_cast<int>((m + (m >> 4)) & 0x0Fu);
}
static_assert(bits8(0) == 0 && bits8(0xFF) == 8 && bits8(0xA5) == 4 && bits8(0x80) == 1);

// The same for all 8 lanes (the caller masks those past the node's children).
inline unsigned closerThan(const Lanes& s, const Point3f& p, float r2) {
  return closerThan4(s.x, s.y, s.z, p, r2) | closerThan4(s.x + 4, s.y + 4, s.z + 4, p, r2) << 4;
}

// Body-body descent. The inner tests run in body a's frame: a's node centres are the tree's
// own (no transform), b's are carried into a's frame by the relative pose, so half the centre
// transforms of a world-frame descent are saved. They run in single precision, on the trees'
// float centres (SphereTreeLevel::floatCenters), 8 children at a time, and are widened by
// `slack_` (the rounding of a double test in a's frame, against the world-frame leaf test) and
// by `floatSlack_` (the rounding of the float test against the double one), so they may let
// through a pair that an exact test would drop, never the reverse. A leaf pair is decided, and
// its contact computed, from world centres in double by the expressions a world-frame descent
// uses: the same contacts, to the bit, in the same order (the order follows the children's
// order, not the tests); every scene's checksum stayed the same.
class TreeTreeDescent {
 public:
  TreeTreeDescent(const Collider& a, const Collider& b, std::vector<Contact>& out,
                  PairCandidates* memo)
      : a_(a), b_(b), ta_(*a.tree), tb_(*b.tree), out_(out), memo_(memo) {}

  std::uint64_t run() {
    ++tests_;
    slack_ = roundingSlack(a_.x, ta_.boundingRadius) + roundingSlack(b_.x, tb_.boundingRadius);
    Rab_ = a_.R.transpose() * b_.R;
    tab_ = a_.R.transpose() * (b_.x - a_.x);
    // The float tests' rounding (u = 2^-24). Every centre of a's tree lies within
    // ta_.centerBound of a's origin, every centre of b's within tb_.centerBound of b's, which is
    // |tab_| away; let M = |tab_| + both bounds. A centre rounded to float is off by at most
    // sqrt(3) u M; one carried into the other body's frame in float (rotation, translation and
    // centre rounded, three products and three sums) by at most 6 u M per coordinate, 11 u M
    // in all; their difference, its squared norm and the squared radius add a few u M more:
    // about 21 u M. 2^-16 M = 256 u M is over ten times that, and a small fraction of a leaf
    // radius for bodies of similar size (M is about their size), so it lets through few pairs
    // more.
    floatSlack_ = std::ldexp(tab_.norm() + ta_.centerBound + tb_.centerBound, -16);
    if (memo_ && planCandidates()) {  // the candidates hold: test only them
      serveCandidates();
      return tests_;
    }
    const double reach = ta_.boundingRadius + tb_.boundingRadius + slack_ + margin_;
    if ((a_.x - b_.x).squaredNorm() >= reach * reach) {
      if (margin_ > 0) indexCandidates();
      return tests_;
    }
    for (int r = 0; r < 3; ++r) {
      tf_[r] = static_cast<float>(tab_[r]);
      for (int c = 0; c < 3; ++c) Rf_[3 * r + c] = static_cast<float>(Rab_(r, c));
    }
    // Level 0 is a single voxel; the bounding spheres above stand in for it.
    descend(0, 0, Point3f{0, 0, 0}, 0, 0, Point3f{tf_[0], tf_[1], tf_[2]});
    if (margin_ > 0) indexCandidates();
    return tests_;
  }

 private:
  // Arranges freshly built candidates for serveCandidates: runs sharing a's leaf (the descent
  // stored a's leaf in its outer loop), and b's leaf centres per candidate in float, x of
  // every candidate, then y, then z, each block padded by 4 lanes.
  void indexCandidates() {
    PairCandidates& m = *memo_;
    const std::size_t n = m.leaves.size() / 2;
    m.runs.clear();
    for (std::size_t k = 0; k < n; ++k)
      if (k == 0 || m.leaves[2 * k] != m.leaves[2 * k - 2])
        m.runs.push_back(static_cast<std::uint32_t>(k));
    m.runs.push_back(static_cast<std::uint32_t>(n));
    const SphereTreeLevel& lb = tb_.leaves();
    const std::size_t s = n + 4;
    m.centersB.assign(3 * s, 0.0f);
    for (std::size_t k = 0; k < n; ++k)
      for (int d = 0; d < 3; ++d) m.centersB[d * s + k] = lb.floatAxis(d)[m.leaves[2 * k + 1]];
  }

  // Tests only the stored candidates. Most of a resting pair's do not touch (a leaf's
  // neighbours within the margin beside the one it touches), so each is first tested in body
  // b's frame in float, widened as the descent's tests are (the rounding slack covers a
  // relative pose in either body's frame as it covers a's): a pair that misses there misses
  // exactly too. a's leaf is carried into b's frame once per run of candidates that share it,
  // and tested against 4 of b's at a time, whose centres lie in a row (indexCandidates). The
  // rest are decided by the leaf test itself, from world centres as the descent decides them,
  // in the candidates' order; a's world centre is computed once per run (the same
  // expression, the same bits).
  void serveCandidates() {
    const PairCandidates& m = *memo_;
    const std::vector<std::uint32_t>& leaves = m.leaves;
    const std::size_t n = leaves.size() / 2, s = n + 4;
    tests_ += n;
    const double reach = ta_.leaves().radius + tb_.leaves().radius + slack_ + floatSlack_;
    const float reach2 = static_cast<float>(reach * reach);
    const Mat3 Rba = Rab_.transpose();
    const Vec3 tba = -(Rba * tab_);
    float R[9], t[3];
    for (int r = 0; r < 3; ++r) {
      t[r] = static_cast<float>(tba[r]);
      for (int c = 0; c < 3; ++c) R[3 * r + c] = static_cast<float>(Rba(r, c));
    }
    const SphereTreeLevel& la = ta_.leaves();
    const float *ax = la.floatAxis(0), *ay = la.floatAxis(1), *az = la.floatAxis(2);
    const float* bx = m.centersB.data();
    const float* by = bx + s;
    const float* bz = by + s;
    static thread_local std::vector<std::uint32_t> pass;
    pass.resize(n);
    std::size_t passed = 0;
    for (std::size_t r = 0; r + 1 < m.runs.size(); ++r) {
      const std::uint32_t begin = m.runs[r], end = m.runs[r + 1];
      const std::uint32_t i = leaves[2 * begin];
      const float x = ax[i], y = ay[i], z = az[i];
      const Point3f p{t[0] + R[0] * x + R[1] * y + R[2] * z, t[1] + R[3] * x + R[4] * y + R[5] * z,
                      t[2] + R[6] * x + R[7] * y + R[8] * z};
      for (std::uint32_t k = begin; k < end; k += 4) {
        unsigned hits = closerThan4(bx + k, by + k, bz + k, p, reach2);
        if (end - k < 4) hits &= (1u << (end - k)) - 1;
        for (; hits; hits &= hits - 1) pass[passed++] = k + __builtin_ctz(hits);
      }
    }
    std::uint32_t lastI = UINT32_MAX;
    Vec3 wa = Vec3::Zero();
    for (std::size_t q = 0; q < passed; ++q) {
      const std::uint32_t i = leaves[2 * pass[q]], j = leaves[2 * pass[q] + 1];
      if (i != lastI) lastI = i, wa = leafWorldA(i);
      emit(i, wa, j, leafWorldB(j));
    }
  }

  // The squared radius of the widened float test between a node of a at level la and one of b
  // at level lb.
  float reach2(int la, int lb) const {
    const double r = ta_.levels[la].radius + tb_.levels[lb].radius + slack_ + margin_ + floatSlack_;
    return static_cast<float>(r * r);
  }

  // The children of node i at level l of tree a (centres as they are) or b (carried into a's
  // frame), 8 lanes loaded whatever their number (the level's float centres are padded);
  // returns their number.
  int childrenA(int l, std::uint32_t i, std::uint32_t& first, Lanes& kids) const {
    const SphereTreeLevel& next = ta_.levels[l + 1];
    first = ta_.levels[l].childBegin[i];
    const float *x = next.floatAxis(0) + first, *y = next.floatAxis(1) + first,
                *z = next.floatAxis(2) + first;
    for (int k = 0; k < kLanes; ++k) {
      kids.x[k] = x[k];
      kids.y[k] = y[k];
      kids.z[k] = z[k];
    }
    return static_cast<int>(ta_.levels[l].childBegin[i + 1] - first);
  }
  int childrenB(int l, std::uint32_t i, std::uint32_t& first, Lanes& kids) const {
    const SphereTreeLevel& next = tb_.levels[l + 1];
    first = tb_.levels[l].childBegin[i];
    const float *fx = next.floatAxis(0) + first, *fy = next.floatAxis(1) + first,
                *fz = next.floatAxis(2) + first;
    const float* R = Rf_;
    for (int k = 0; k < kLanes; ++k) {
      const float x = fx[k], y = fy[k], z = fz[k];
      kids.x[k] = tf_[0] + R[0] * x + R[1] * y + R[2] * z;
      kids.y[k] = tf_[1] + R[3] * x + R[4] * y + R[5] * z;
      kids.z[k] = tf_[2] + R[6] * x + R[7] * y + R[8] * z;
    }
    return static_cast<int>(tb_.levels[l].childBegin[i + 1] - first);
  }

  // Whether the stored candidates serve this test; if not, whether this descent builds new
  // ones (margin_ > 0). See PairCandidates (narrow_phase.h).
  bool planCandidates() {
    PairCandidates& m = *memo_;
    // How far any leaf centre of b may have moved relative to a since a pose (the Frobenius
    // norm bounds the spectral one).
    auto moved = [&](const Mat3& R, const Vec3& t) {
      return (Rab_ - R).norm() * tb_.boundingRadius + (tab_ - t).norm();
    };
    const double margin = kCandidateMargin * (ta_.leaves().radius + tb_.leaves().radius);
    const CandidatePlan plan =
        chooseCandidatePlan(m, m.holds ? moved(m.buildR, m.buildT) : INFINITY,
                            m.hasLast ? moved(m.lastR, m.lastT) : INFINITY, margin, slack_);
    m.served = plan == CandidatePlan::kServe;
    if (m.served) return true;
    m.hasLast = true;
    m.lastR = Rab_;
    m.lastT = tab_;
    m.holds = plan == CandidatePlan::kBuild;
    if (!m.holds) return false;
    m.buildR = Rab_;
    m.buildT = tab_;
    m.margin = margin_ = margin;
    m.leaves.clear();
    return false;
  }

  // Node ia at level la of a (centre ca) and node ib at level lb of b (centre cb, in a's frame)
  // may collide (or are the roots after the bounding-sphere test). A node already at its tree's
  // leaf level stands for itself while the other descends.
  void descend(int la, std::uint32_t ia, const Point3f& ca, int lb, std::uint32_t ib,
               const Point3f& cb) {
    const bool leafA = la == ta_.leafLevel();
    const bool leafB = lb == tb_.leafLevel();
    if (leafA && leafB) {
      ++tests_;
      emit(ia, leafWorldA(ia), ib, leafWorldB(ib));
      return;
    }
    Lanes kidsA, kidsB;
    std::uint32_t firstA = ia, firstB = ib;
    int nA = 1, nB = 1;
    if (leafA)
      kidsA = Lanes::single(ca);
    else
      nA = childrenA(la, ia, firstA, kidsA);
    if (leafB)
      kidsB = Lanes::single(cb);
    else
      nB = childrenB(lb, ib, firstB, kidsB);
    const int kidLevelA = leafA ? la : la + 1;
    const int kidLevelB = leafB ? lb : lb + 1;
    unsigned maskA = (1u << nA) - 1, maskB = (1u << nB) - 1;
    // Early exit: a child that misses the other side's node misses all that node's children
    // (they lie inside it), so it is dropped before the child pairs are tested. The order of
    // the survivors is kept: the contacts and their order are those of the full test.
    if (!leafB && nA > 1) {
      tests_ += nA;
      maskA &= closerThan(kidsA, cb, reach2(kidLevelA, lb));
    }
    if (!leafA && nB > 1) {
      tests_ += nB;
      maskB &= closerThan(kidsB, ca, reach2(la, kidLevelB));
    }
    tests_ += static_cast<std::uint64_t>(bits8(maskA) * bits8(maskB));
    const float r2 = reach2(kidLevelA, kidLevelB);
    const bool kidsLeaves = kidLevelA == ta_.leafLevel() && kidLevelB == tb_.leafLevel();
    for (unsigned mi = maskA; mi; mi &= mi - 1) {
      const int i = __builtin_ctz(mi);
      const unsigned hits = maskB & closerThan(kidsB, kidsA[i], r2);
      if (!hits) continue;
      if (!kidsLeaves) {
        for (unsigned mj = hits; mj; mj &= mj - 1) {
          const int j = __builtin_ctz(mj);
          descend(kidLevelA, firstA + i, kidsA[i], kidLevelB, firstB + j, kidsB[j]);
        }
        continue;
      }
      // Leaf pairs that pass are decided exactly, from world centres in double.
      const Vec3 wa = leafWorldA(firstA + i);
      for (unsigned mj = hits; mj; mj &= mj - 1) {
        const std::uint32_t j = firstB + __builtin_ctz(mj);
        emit(firstA + i, wa, j, leafWorldB(j));
      }
    }
  }

  Vec3 leafWorldA(std::uint32_t i) const { return leafWorldCenter(a_, i); }
  Vec3 leafWorldB(std::uint32_t j) const { return leafWorldCenter(b_, j); }

  // The exact test of a leaf pair, and its contact, in world coordinates; while candidates
  // are built, a pair within the margin is kept as one. The callers count the test. Always
  // inlined into its callers (GCC kept it a call; inlined, Lv 6 crosses 1,320 -> 1,290 ms,
  // stack 207 -> 202 ms).
  __attribute__((always_inline)) void emit(std::uint32_t leafA, const Vec3& ca, std::uint32_t leafB,
                                           const Vec3& cb) {
    const double r = ta_.leaves().radius + tb_.leaves().radius;
    const Vec3 d = ca - cb;
    const double d2 = d.squaredNorm();
    if (margin_ > 0 && d2 < (r + margin_) * (r + margin_)) {
      memo_->leaves.push_back(leafA);
      memo_->leaves.push_back(leafB);
    }
    if (d2 >= r * r) return;
    const double dist = d.norm();
    if (dist == 0.0) return;  // coincident centres: no defined normal (measure zero)
    Contact c;
    c.a = a_.body;
    c.b = b_.body;
    c.point = 0.5 * (ca + cb);  // midpoint of the two centres (fig. 5)
    c.normal = d / dist;        // n21, from body 2 towards body 1
    c.depth = r - dist;
    c.leafA = leafA;
    c.leafB = leafB;
    out_.push_back(c);
  }

  const Collider& a_;
  const Collider& b_;
  const SphereTree& ta_;
  const SphereTree& tb_;
  std::vector<Contact>& out_;
  PairCandidates* memo_;  // null: no temporal coherence
  Mat3 Rab_;              // b's frame -> a's frame: p_a = Rab_ p_b + tab_
  Vec3 tab_;
  float Rf_[9] = {};  // Rab_ and tab_ in single precision, Rf_ row-major
  float tf_[3] = {};
  double slack_ = 0;       // widening of the internal tests, m
  double floatSlack_ = 0;  // their further widening for single precision, m
  double margin_ = 0;      // while building candidates: their margin, m
  std::uint64_t tests_ = 0;
};

// Descends body a's sphere tree alone against something that is not a tree (the floor plane,
// the terrain), as fig. 3 does for two trees: the bounding sphere first, then level 1, then the
// children of every node that may touch. `mayTouch(centre, radius, bound)` may answer yes
// wrongly but never no wrongly (so no colliding leaf is missed); `bound` comes in as what the
// parent node's test left there (+infinity for the bounding sphere and level 1, whose spheres
// need not lie inside it) and may be updated for the node's children, whose spheres lie inside
// the node's. `leaf(node, radius)` emits the contact of a leaf sphere that passed, if it really
// collides. Returns the sphere tests made.
template <class MayTouch, class Leaf>
std::uint64_t descendAlone(const Collider& a, MayTouch mayTouch, Leaf leaf) {
  const SphereTree& tree = *a.tree;
  std::uint64_t tests = 1;
  double rootBound = INFINITY;
  if (!mayTouch(a.x, tree.boundingRadius, rootBound)) return tests;
  // The level-0 voxel is skipped: the bounding sphere above stands in for it.
  auto visit = [&](auto& self, const NodeRef& n, double bound) -> void {
    const SphereTreeLevel& lv = tree.levels[n.level];
    if (n.level == tree.leafLevel()) {
      leaf(n, lv.radius);
      return;
    }
    const SphereTreeLevel& next = tree.levels[n.level + 1];
    for (std::uint32_t i = lv.childBegin[n.index]; i < lv.childBegin[n.index + 1]; ++i) {
      const NodeRef child{n.level + 1, i, a.x + a.R * next.centers[i]};
      ++tests;
      double childBound = bound;
      if (mayTouch(child.center, next.radius, childBound)) self(self, child, childBound);
    }
  };
  visit(visit, NodeRef{0, 0, a.x}, INFINITY);
  return tests;
}

Contact groundContact(const Collider& a, const Collider& ground, const NodeRef& n) {
  Contact c;
  c.a = a.body;
  c.b = ground.body;
  c.leafA = n.index;
  c.leafB = kTerrainLeaf;  // used for the terrain only; the plane's contacts keep leafB = 0
  return c;
}

// Sphere tree against a plane: a sphere touches when its centre is less than its radius above
// the plane (exact). Contact point: the centre projected onto the plane. Inner nodes are tested
// in the body frame (height = n.x - offset + (R^T n).c, no centre transform), widened by
// roundingSlack; leaves are tested and emitted from their world centres by the world-frame
// expressions, so the contacts are exactly the leaves whose world centre is less than a radius
// above the plane, in the children's order.
// `emit(leaf, point, depth)` takes each contact: stored whole (collideTreePlane), or handed to a
// PlanePatch that reduces them as they come (collideTreePlanePatch); a template, so that each
// is inlined into the leaf loops.
// `serve(h0, m, slack)`, when the candidates hold, tests them instead of the default loop below
// (h0: the body origin's height; m: R^T n; slack: the bound on the rounding of the body-frame
// heights h0 + m.c) and returns the tests made; null: the default loop.
template <class Emit, class Serve = std::nullptr_t>
std::uint64_t treePlaneDescent(const Collider& a, const Collider& p, PairCandidates* memo,
                               Emit emitContact, Serve serve = nullptr) {
  const SphereTree& tree = *a.tree;
  auto height = [&](const Vec3& c) { return planeHeight(p, c); };
  std::uint64_t tests = 1;
  const double slack = roundingSlack(a.x, tree.boundingRadius) + 1e-9 * std::abs(p.offset);
  const double h0 = height(a.x);
  const Vec3 m = a.R.transpose() * p.normal;
  const int leafLevel = tree.leafLevel();
  const double leafRadius = tree.leaves().radius;
  auto emit = [&](std::uint32_t leaf, const Vec3& center, double h) {
    emitContact(leaf, Vec3(center - h * p.normal), leafRadius - h);
  };
  // Temporal coherence (PairCandidates): a leaf's height is h0 + m . c, so it moved by at
  // most |dh0| + |dm| times the bounding radius since a pose.
  double margin = 0;
  if (memo) {
    auto moved = [&](const Vec3& mm, double hh) {
      return std::abs(h0 - hh) + (m - mm).norm() * tree.boundingRadius;
    };
    const double candidateMargin = kCandidateMargin * leafRadius;
    const CandidatePlan plan = chooseCandidatePlan(
        *memo, memo->holds ? moved(memo->buildT, memo->buildH) : INFINITY,
        memo->hasLast ? moved(memo->lastT, memo->lastH) : INFINITY, candidateMargin, slack);
    memo->served = plan == CandidatePlan::kServe;
    if constexpr (!std::is_same_v<Serve, std::nullptr_t>) {
      if (memo->served && leafLevel > 0) return tests + serve(h0, m, slack);
    }
    if (memo->served) {
      for (std::uint32_t i : memo->leaves) {
        ++tests;
        const Vec3 center = leafWorldCenter(a, i);
        const double h = height(center);
        if (h < leafRadius) emit(i, center, h);
      }
      return tests;
    }
    memo->holds = plan == CandidatePlan::kBuild;
    memo->hasLast = true;
    memo->lastT = m;
    memo->lastH = h0;
    if (memo->holds) {
      memo->buildT = m;
      memo->buildH = h0;
      memo->margin = margin = candidateMargin;
      memo->leaves.clear();
    }
  }
  // A leaf: the exact test, and while candidates are built, the margin's.
  auto leaf = [&](std::uint32_t i) {
    const Vec3 center = leafWorldCenter(a, i);
    const double h = height(center);
    if (margin > 0 && h < leafRadius + margin) memo->leaves.push_back(i);
    if (h < leafRadius) emit(i, center, h);
  };
  if (!(h0 < tree.boundingRadius + slack + margin)) return tests;
  if (leafLevel == 0) {  // a one-level tree: its root is its leaf, at the body origin
    leaf(0);
    return tests;
  }
  // The level-0 voxel is skipped: the bounding sphere above stands in for it.
  auto visit = [&](auto& self, int level, std::uint32_t index) -> void {
    const SphereTreeLevel& lv = tree.levels[level];
    const SphereTreeLevel& next = tree.levels[level + 1];
    const bool leaves = level + 1 == leafLevel;
    for (std::uint32_t i = lv.childBegin[index]; i < lv.childBegin[index + 1]; ++i) {
      ++tests;
      if (!leaves) {
        if (h0 + m.dot(next.centers[i]) < next.radius + slack + margin) self(self, level + 1, i);
        continue;
      }
      leaf(i);
    }
  };
  visit(visit, 0, 0);
  if (margin > 0) {  // candidates built: their groups' bounds (servePlanePatch)
    const std::vector<Vec3>& centers = tree.leaves().centers;
    const std::size_t groups = (memo->leaves.size() + kPatchGroup - 1) / kPatchGroup;
    memo->groupLo.assign(groups, Vec3::Constant(INFINITY));
    memo->groupHi.assign(groups, Vec3::Constant(-INFINITY));
    for (std::size_t k = 0; k < memo->leaves.size(); ++k) {
      const Vec3& c = centers[memo->leaves[k]];
      memo->groupLo[k / kPatchGroup] = memo->groupLo[k / kPatchGroup].cwiseMin(c);
      memo->groupHi[k / kPatchGroup] = memo->groupHi[k / kPatchGroup].cwiseMax(c);
    }
  }
  return tests;
}

std::uint64_t collideTreePlane(const Collider& a, const Collider& p, std::vector<Contact>& out,
                               PairCandidates* memo) {
  return treePlaneDescent(a, p, memo, [&](std::uint32_t leaf, const Vec3& point, double depth) {
    Contact c;
    c.a = a.body;
    c.b = p.body;
    c.leafA = leaf;
    c.normal = p.normal;
    c.point = point;
    c.depth = depth;
    out.push_back(c);
  });
}

std::uint64_t collideTreePlane(const Collider& a, const Collider& p, std::vector<Contact>& out) {
  return collideTreePlane(a, p, out, nullptr);
}

// The reduction of a body's plane contacts when its candidates hold, without computing every
// contact: what PlanePatch::finish makes of the contacts the candidates give, bit for bit
// (contact_reduction_test compares the two step after step). A contact's exact values (world
// centre, height, point: the expressions of treePlaneDescent's leaf test) are computed only
// where they can decide something. The argument: a leaf's body-frame height h0 + m.c, the
// expression of the descent's inner tests, differs from its exact height by rounding only, at
// most `slack` (the descent's own bound), and over a group of candidates (kPatchGroup
// consecutive ones) the body-frame heights and plane coordinates u0 + u.c are linear in the
// centre, so the group's box of centres (PairCandidates::groupLo, groupHi) bounds them; widened
// by slack (flatSlack for coordinates, built alike) the bounds hold the exact values. So:
//  - a group wholly below r - slack holds only contacts, one wholly at or above r + slack none;
//    in any other group each candidate's body-frame height decides, and its exact test where
//    that lies within slack of r;
//  - the deepest contact (the first of the largest exact depth r - h) has a body-frame height
//    within 3 slack of the lowest one: any leaf higher than that is exactly higher by more than
//    slack, far more than a rounding of r - h could make up, so its depth is smaller. Groups
//    whose bounds lie above that are not looked into (for a face at rest, the groups of its
//    lowest corner are), and only leaves within it get exact depths;
//  - the other representatives come from chooseRepresentatives with the groups' boxes: a
//    group's exact values are computed only when its box could hold a better point.
// The contact count is exact, so a patch of at most kContactsPerPatch contacts is emitted whole,
// as finish emits it. Counted as one test per candidate, as the plain loop counts.
struct PlaneServeScratch {
  // Per group of candidates that holds contacts (in order): its candidates' range, its
  // contacts' first index, whether every candidate is a contact (else its contacts' candidate
  // indices are member[members...]), and the bounds of its body-frame heights.
  struct Group {
    std::size_t begin, end, first, members;
    bool all;
    double lo, hi;
  };
  std::vector<Group> groups;
  std::vector<std::size_t> member;      // per contact of a mixed group: its candidate index
  std::vector<std::size_t> groupBegin;  // contact index ranges, for chooseRepresentatives
  std::vector<PatchBox> boxes;
  std::vector<char> filled;           // per group: its contacts' exact values computed
  std::vector<Eigen::Vector2d> flat;  // per contact, exact, where computed
  std::vector<Vec3> point;
  std::vector<double> depth;
  std::vector<std::uint32_t> leaf;
};

// The range of h0 + m.c over the box [lo, hi] of c.
inline void linearRange(double h0, const Vec3& m, const Vec3& lo, const Vec3& hi, double& a,
                        double& b) {
  a = h0, b = h0;
  for (int k = 0; k < 3; ++k) {
    const double x = m[k] * lo[k], y = m[k] * hi[k];
    a += std::min(x, y), b += std::max(x, y);
  }
}

std::uint64_t servePlanePatch(const Collider& a, const Collider& p, const PairCandidates& memo,
                              double h0, const Vec3& m, double slack, std::vector<Contact>& out,
                              std::uint64_t& leafContacts) {
  static thread_local PlaneServeScratch s;
  const SphereTree& tree = *a.tree;
  const std::vector<Vec3>& centers = tree.leaves().centers;
  const double r = tree.leaves().radius;
  const Vec3& n = p.normal;
  Vec3 t1, t2;
  patchPlaneBasis(n, t1, t2);
  const Vec3 u1 = a.R.transpose() * t1, u2 = a.R.transpose() * t2;
  const double o1 = a.x.dot(t1), o2 = a.x.dot(t2);
  const double flatSlack =
      1e-9 * (1 + a.x.norm() + 2 * tree.boundingRadius + std::abs(p.offset) + std::abs(h0));
  // The exact values of leaf i, by treePlaneDescent's expressions.
  auto exact = [&](std::uint32_t i, Vec3& point, double& h) {
    const Vec3 center = leafWorldCenter(a, i);
    h = planeHeight(p, center);
    point = center - h * n;
  };
  auto bodyHeight = [&](std::size_t k) { return h0 + m.dot(centers[memo.leaves[k]]); };
  const std::size_t candidates = memo.leaves.size();
  s.groups.clear();
  s.member.clear();
  s.boxes.clear();
  std::size_t count = 0;
  double lowestUpper = INFINITY;  // at least the lowest body-frame height of a contact
  for (std::size_t g = 0; g * kPatchGroup < candidates; ++g) {
    // Written in place and dropped where it holds no contact: built on the stack and copied,
    // it costs the copy's loads a stalled store forwarding each (perf annotate).
    PlaneServeScratch::Group& G = s.groups.emplace_back();
    G.begin = g * kPatchGroup;
    G.end = std::min(candidates, (g + 1) * kPatchGroup);
    G.first = count;
    G.members = s.member.size();
    G.all = true;
    linearRange(h0, m, memo.groupLo[g], memo.groupHi[g], G.lo, G.hi);
    G.lo -= slack, G.hi += slack;  // the rounding of the range itself
    if (G.lo >= r + slack) {
      s.groups.pop_back();
      continue;
    }
    if (G.hi < r - slack) {
      count += G.end - G.begin;
      lowestUpper = std::min(lowestUpper, G.hi);
    } else {  // each candidate decides
      G.all = false;
      for (std::size_t k = G.begin; k < G.end; ++k) {
        const double hb = bodyHeight(k);
        if (!(hb < r - slack)) {
          if (hb >= r + slack) continue;
          Vec3 point;
          double h;
          exact(memo.leaves[k], point, h);
          if (!(h < r)) continue;
        }
        s.member.push_back(k);
        lowestUpper = std::min(lowestUpper, hb);
        ++count;
      }
      if (count == G.first) {
        s.groups.pop_back();
        continue;
      }
    }
    double f1lo, f1hi, f2lo, f2hi;
    linearRange(o1, u1, memo.groupLo[g], memo.groupHi[g], f1lo, f1hi);
    linearRange(o2, u2, memo.groupLo[g], memo.groupHi[g], f2lo, f2hi);
    PatchBox box;
    box.extend(Eigen::Vector2d(f1lo - flatSlack, f2lo - flatSlack));
    box.extend(Eigen::Vector2d(f1hi + flatSlack, f2hi + flatSlack));
    s.boxes.push_back(box);
  }
  leafContacts += count;
  if (count == 0) return candidates;
  if (s.flat.size() < count) {  // grown, never shrunk: no clearing per call
    s.flat.resize(count);
    s.point.resize(count);
    s.depth.resize(count);
    s.leaf.resize(count);
  }
  s.groupBegin.resize(s.groups.size() + 1);
  for (std::size_t g = 0; g < s.groups.size(); ++g) s.groupBegin[g] = s.groups[g].first;
  s.groupBegin[s.groups.size()] = count;
  s.filled.assign(s.groups.size(), 0);
  // The candidate index of contact j of group G.
  auto candidateOf = [&](const PlaneServeScratch::Group& G, std::size_t j) {
    return G.all ? G.begin + (j - G.first) : s.member[G.members + (j - G.first)];
  };
  auto fill = [&](std::size_t g) {
    if (s.filled[g]) return;
    s.filled[g] = 1;
    const PlaneServeScratch::Group& G = s.groups[g];
    for (std::size_t j = G.first; j < s.groupBegin[g + 1]; ++j) {
      const std::uint32_t i = memo.leaves[candidateOf(G, j)];
      double h;
      exact(i, s.point[j], h);
      s.leaf[j] = i;
      s.depth[j] = r - h;
      s.flat[j] = Eigen::Vector2d(s.point[j].dot(t1), s.point[j].dot(t2));
    }
  };
  auto contact = [&](std::size_t j) {
    Contact c;
    c.a = a.body;
    c.b = p.body;
    c.point = s.point[j];
    c.normal = n;
    c.depth = s.depth[j];
    c.leafA = s.leaf[j];
    out.push_back(c);
  };
  if (count <= static_cast<std::size_t>(kContactsPerPatch)) {  // as they are, deepest first
    for (std::size_t g = 0; g < s.groups.size(); ++g) fill(g);
    std::size_t order[kContactsPerPatch];
    deepestFirst(s.depth.data(), count, order);
    for (std::size_t j = 0; j < count; ++j) contact(order[j]);
    return candidates;
  }
  // The lowest body-frame height of a contact: in the groups that may hold it.
  const double reach = lowestUpper + 3 * slack;
  double lowest = INFINITY;
  for (std::size_t g = 0; g < s.groups.size(); ++g) {
    const PlaneServeScratch::Group& G = s.groups[g];
    if (G.lo > reach) continue;
    for (std::size_t j = G.first; j < s.groupBegin[g + 1]; ++j)
      lowest = std::min(lowest, bodyHeight(candidateOf(G, j)));
  }
  // The deepest: exact depths of the contacts within 3 slack of it, the first of the largest.
  std::size_t deepest = count;
  for (std::size_t g = 0; g < s.groups.size(); ++g) {
    const PlaneServeScratch::Group& G = s.groups[g];
    if (G.lo > lowest + 3 * slack) continue;
    for (std::size_t j = G.first; j < s.groupBegin[g + 1]; ++j) {
      if (bodyHeight(candidateOf(G, j)) > lowest + 3 * slack) continue;
      fill(g);
      if (deepest == count || s.depth[j] > s.depth[deepest]) deepest = j;
    }
  }
  std::size_t keep[kContactsPerPatch];
  // (A std::function holding only a pointer stays in its small buffer: no allocation.)
  const auto* fillGroup = &fill;
  const int kept = chooseRepresentatives(
      count, deepest, s.flat.data(), s.boxes.data(), s.groupBegin.data(), s.groups.size(),
      [fillGroup](std::size_t g) { (*fillGroup)(g); }, keep);
  for (int k = 0; k < kept; ++k) contact(keep[k]);
  return candidates;
}

// The contacts handed to `patch` and reduced there into `out` (served candidates: reduced
// without computing every contact, servePlanePatch). Adds the leaf contacts to leafContacts.
std::uint64_t collideTreePlanePatch(const Collider& a, const Collider& p, PairCandidates* memo,
                                    PlanePatch& patch, std::vector<Contact>& out,
                                    std::uint64_t& leafContacts) {
  patch.start(p.normal);
  bool served = false;
  const std::uint64_t tests = treePlaneDescent(
      a, p, memo,
      [&](std::uint32_t leaf, const Vec3& point, double depth) { patch.add(point, depth, leaf); },
      [&](double h0, const Vec3& m, double slack) {
        served = true;
        return servePlanePatch(a, p, *memo, h0, m, slack, out, leafContacts);
      });
  if (served) return tests;
  leafContacts += patch.size();
  patch.finish(a.body, p.body, out);
  return tests;
}

// Sphere tree against terrain. A node may touch unless its sphere lies entirely above the
// highest sample under its footprint (a child's sphere lies in its parent's, so this never
// drops a node with colliding leaves). A leaf sphere collides if its centre is below the
// surface or the nearest surface triangle is closer than its radius; its contact point is that
// nearest surface point, its normal points from there to the centre (the surface normal when
// the centre is below the surface).
//
// The terrain is solid below its surface, so where the grid ends its border is a vertical wall
// from the border's surface line down (the paper has no terrain edges; voxfall's decision). A
// leaf sphere whose centre lies outside the grid, lower than the surface at the nearest border
// point, and closer to that point than its radius touches the wall there, with a horizontal
// normal. Without the wall, a rock that leaves a raised grid onto the floor plane of the paper's
// cliff scene (or is pushed off it by a pile) meets no terrain at the border and slides under the
// surface: 2-9 m deep by the true-mesh check, until the rock monitor buries it.
//
// Temporal coherence (PairCandidates; the terrain does not move, so the pair's pose is the
// body's). Why a margin bounds what a motion can change, although the leaf test is not
// Lipschitz in the centre (near a NODATA hole a centre deep below a cell is far from every
// triangle): the argument is containment, as for the plain descent. A node is dropped when its
// sphere S lies above `surfaceBoundNear` over S's footprint square, is clear of its planes, or
// lies above the surface by `sphereAbove`, and every way a sphere s inside S could touch (its
// centre below the surface, a triangle point inside it, the border wall beside it) needs a
// surface or wall point inside S or under that bound inside the square: none. A
// leaf that the descent widened by the margin m did not reach had such an S, of radius at least
// its own plus m, about its old centre; while no leaf centre has moved by m since, the leaf's
// sphere still lies inside S, so it does not touch. Every touching leaf is then a candidate,
// and the candidates are tested in the descent's order by the leaf test itself: the same
// contacts, bit for bit. The inner tests are widened by the rounding slack, as the plane's are.
std::uint64_t collideTreeHeightfield(const Collider& a, const Collider& t,
                                     std::vector<Contact>& out, PairCandidates* memo) {
  const Heightfield& field = *t.terrain;
  const SphereTree& tree = *a.tree;
  const double xEnd = field.x0 + (field.nx - 1) * field.cell;
  const double yEnd = field.y0 + (field.ny - 1) * field.cell;
  const double slack = roundingSlack(a.x, tree.boundingRadius);
  double widen = slack;  // added to every inner radius: the slack, and while building the margin
  // A child's sphere lies in its parent's, so the cells under it are some of the parent's and
  // the highest sample under it is no higher than the parent's: a child whose sphere lies above
  // that is dropped without looking the cells up (the same answer, cheaper; with 1,000 rocks the
  // lookups are otherwise a third of the terrain narrow phase's time).
  // An inner node that passes the bound and the planes gets the exact test, sphereAbove (a
  // leaf's own test is exact already). Near a ridge the planes keep nodes however far they are
  // from the surface (the other triangle's extended plane rises above it): a rock bouncing
  // down the Tyrol DEM's 5 m cells takes 83 leaf tests a step without it, for 0.06 contacts; 2.9
  // with it.
  const double leafRadius = tree.leaves().radius;
  auto mayTouch = [&](const Vec3& c, double r, double& bound) {
    const bool inner = r > leafRadius;
    r += widen;
    if (c.z() - r >= bound) return false;
    bool clear;
    bound = field.surfaceBoundNear(c, r, clear);
    if (clear || c.z() - r >= bound) return false;
    return !inner || !field.sphereAbove(c, r);
  };
  auto leaf = [&](const NodeRef& n, double r) {
    const Vec3& c = n.center;
    Contact k = groundContact(a, t, n);
    const double h = field.heightAt(c.x(), c.y());
    if (!std::isnan(h) && c.z() < h) {  // centre inside the terrain
      k.normal = field.normalAt(c.x(), c.y());
      k.point = Vec3(c.x(), c.y(), h);
      k.depth = r + (h - c.z()) * k.normal.z();
      out.push_back(k);
      return;
    }
    const Vec3 border(std::clamp(c.x(), field.x0, xEnd), std::clamp(c.y(), field.y0, yEnd), c.z());
    if (border.x() != c.x() || border.y() != c.y()) {  // centre outside the grid
      const double hb = field.heightAt(border.x(), border.y());
      const double d = (c - border).norm();  // horizontal: same z
      if (!std::isnan(hb) && c.z() < hb) {   // beside the wall, below its top
        if (d < r) {
          k.normal = (c - border) / d;
          k.point = border;
          k.depth = r - d;
          out.push_back(k);
        }
        return;  // the wall is nearer than the surface above it
      }
    }
    int i0, i1, j0, j1;
    field.cellRange(c.x(), c.y(), r, i0, i1, j0, j1);
    double best = r * r;
    Vec3 nearest;
    bool found = false;
    Vec3 tri[2][3];
    for (int j = j0; j <= j1; ++j)
      for (int i = i0; i <= i1; ++i) {
        if (!field.hasCell(i, j)) continue;
        field.cellTriangles(i, j, tri);
        for (const auto& tr : tri) {
          // The triangle lies in its plane, so it holds no point nearer than the plane: a
          // triangle whose plane is farther than sqrt(best) is skipped (4 of 5 with 1,000
          // rocks, whose leaf tests mostly find nothing). The comparison allows a relative
          // 1e-9 for rounding, so it never skips a triangle that would have won: the same
          // nearest point, bit for bit.
          const Vec3 normal = (tr[1] - tr[0]).cross(tr[2] - tr[0]);
          const double s = normal.dot(c - tr[0]);
          if (s * s > best * normal.squaredNorm() * (1 + 1e-9)) continue;
          const Vec3 q = closestPointOnTriangle(c, tr[0], tr[1], tr[2]);
          const double d2 = (c - q).squaredNorm();
          if (d2 < best) best = d2, nearest = q, found = true;
        }
      }
    if (!found) return;
    const double d = std::sqrt(best);
    if (d == 0.0) return;  // centre exactly on the surface: no defined normal (measure zero)
    k.normal = (c - nearest) / d;
    k.point = nearest;
    k.depth = r - d;
    out.push_back(k);
  };
  if (!memo) return descendAlone(a, mayTouch, leaf);

  const int leafLevel = tree.leafLevel();
  // How far any leaf centre (within the bounding radius of the origin) moved since a pose.
  auto moved = [&](const Mat3& R, const Vec3& x) {
    return (a.x - x).norm() + (a.R - R).norm() * tree.boundingRadius;
  };
  const double margin = kCandidateMargin * leafRadius;
  const CandidatePlan plan = chooseCandidatePlan(
      *memo, memo->holds ? moved(memo->buildR, memo->buildT) : INFINITY,
      memo->hasLast ? moved(memo->lastR, memo->lastT) : INFINITY, margin, slack);
  memo->served = plan == CandidatePlan::kServe;
  if (memo->served) {
    std::uint64_t tests = 0;
    for (std::uint32_t i : memo->leaves) {
      ++tests;
      leaf(NodeRef{leafLevel, i, leafWorldCenter(a, i)}, leafRadius);
    }
    return tests;
  }
  memo->hasLast = true;
  memo->lastR = a.R;
  memo->lastT = a.x;
  memo->holds = plan == CandidatePlan::kBuild;
  if (!memo->holds) return descendAlone(a, mayTouch, leaf);
  memo->buildR = a.R;
  memo->buildT = a.x;
  memo->margin = margin;
  memo->leaves.clear();
  widen = slack + margin;
  // Every leaf the widened descent reaches is a candidate.
  return descendAlone(a, mayTouch, [&](const NodeRef& n, double r) {
    memo->leaves.push_back(n.index);
    leaf(n, r);
  });
}

std::uint64_t collideTreeHeightfield(const Collider& a, const Collider& t,
                                     std::vector<Contact>& out) {
  return collideTreeHeightfield(a, t, out, nullptr);
}

std::uint64_t collideTreeTree(const Collider& a, const Collider& b, std::vector<Contact>& out) {
  return TreeTreeDescent(a, b, out, nullptr).run();
}

using CollideFn = std::uint64_t (*)(const Collider&, const Collider&, std::vector<Contact>&);

// Which pair does what. Rows: type of a (body 1); columns: type of b (body 2). The plane and
// the terrain are always body 2 (they never move), so their rows are empty. A scene uses one
// method for all its bodies (sphere trees or polygons), so the two never meet.
constexpr int kTypes = static_cast<int>(ColliderType::kCount);
constexpr CollideFn kCollide[kTypes][kTypes] = {
    //                  kSphereTree      kPlane               kHeightfield     kPolygon
    /* kSphereTree  */ {collideTreeTree, collideTreePlane, collideTreeHeightfield, nullptr},
    /* kPlane       */ {nullptr, nullptr, nullptr, nullptr},
    /* kHeightfield */ {nullptr, nullptr, nullptr, nullptr},
    /* kPolygon     */
    {nullptr, collidePolygonPlane, collidePolygonHeightfield, collidePolygonPolygon},
};

// Fewer collider pairs than this per thread are not worth waking a worker for (that costs about
// as much as a few dozen sphere-tree descents at rest).
constexpr int kJobsPerThread = 16;
// Blocks of work per thread: enough that a thread that drew cheap blocks takes more.
constexpr int kBlocksPerThread = 16;

}  // namespace

// A body's collider of the given type at pose (x, q).
static Collider posedCollider(ColliderType type, int body, const Vec3& x, const Quat& q) {
  Collider c;
  c.type = type;
  c.body = body;
  c.x = x;
  c.R = q.toRotationMatrix();
  return c;
}

Collider sphereTreeCollider(int body, const SphereTree& tree, const Vec3& x, const Quat& q) {
  Collider c = posedCollider(ColliderType::kSphereTree, body, x, q);
  c.tree = &tree;
  return c;
}

Collider polygonCollider(int body, const ConvexPolyhedron& polyhedron, const Vec3& x,
                         const Quat& q) {
  Collider c = posedCollider(ColliderType::kPolygon, body, x, q);
  c.polyhedron = &polyhedron;
  return c;
}

Collider heightfieldCollider(const Heightfield& terrain) {
  Collider c;
  c.type = ColliderType::kHeightfield;
  c.body = kGround;
  c.terrain = &terrain;
  return c;
}

Vec3 closestPointOnTriangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  TriangleFeature feature;
  return closestPointOnTriangle(p, a, b, c, feature);
}

Collider planeCollider(double height) {
  Collider c;
  c.type = ColliderType::kPlane;
  c.body = kGround;
  c.normal = Vec3::UnitZ();
  c.offset = height;
  return c;
}

std::uint64_t collide(const Collider& a, const Collider& b, std::vector<Contact>& out) {
  const CollideFn fn = kCollide[static_cast<int>(a.type)][static_cast<int>(b.type)];
  VF_ASSERT(fn != nullptr);
  return fn(a, b, out);
}

ContactCounts findContacts(const std::vector<BodyInfo>& bodies,
                           const std::vector<BodyState>& states, const std::vector<BodyPair>& pairs,
                           const std::optional<double>& groundHeight, const Heightfield* terrain,
                           WorkerPool* pool, std::vector<Contact>& out, CandidateCache* candidates,
                           bool reduce) {
  // Scratch reused from call to call (per thread: ensembles step worlds on several), so that
  // a step allocates nothing here once warm; for one rock on a terrain, allocating per call
  // costs about 5 % of a step's instructions.
  struct Scratch {
    std::vector<Collider> posed;  // each active body's collider, posed once per call
    std::vector<std::pair<const Collider*, const Collider*>> jobs;
    std::vector<PairCandidates*> memo;
    std::vector<std::vector<Contact>> found;
    std::vector<ContactCounts> counts;
    std::vector<std::pair<std::uint64_t, std::uint32_t>> kept;  // the cache's next pair list
  };
  static thread_local Scratch scratch;
  // Each body's collider once (a rock is in about three jobs a step, and a job holding two
  // whole colliders takes 320 bytes to write and to stride over).
  std::vector<Collider>& posed = scratch.posed;
  posed.resize(bodies.size());
  WorkerPool::forRanges(
      pool, static_cast<int>(bodies.size()), WorkerPool::kBodiesPerRange, [&](int lo, int hi) {
        for (int i = lo; i < hi; ++i) {
          if (!bodies[i].active) continue;
          const Shape& s = *bodies[i].shape;
          posed[i] = s.polyhedron ? polygonCollider(i, *s.polyhedron, states[i].x, states[i].q)
                                  : sphereTreeCollider(i, *s.tree, states[i].x, states[i].q);
        }
      });
  // The collider pairs of this step, in the order their contacts must come out.
  std::vector<std::pair<const Collider*, const Collider*>>& jobs = scratch.jobs;
  jobs.clear();
  for (const BodyPair& p : pairs)  // a pair of which nothing moves (asleep, static) has no news
    if (bodies[p.a].moves() || bodies[p.b].moves()) jobs.emplace_back(&posed[p.a], &posed[p.b]);
  const Collider plane = groundHeight ? planeCollider(*groundHeight) : Collider{};
  if (groundHeight)
    for (std::size_t i = 0; i < bodies.size(); ++i)
      if (bodies[i].moves()) jobs.emplace_back(&posed[i], &plane);
  const Collider field = terrain ? heightfieldCollider(*terrain) : Collider{};
  if (terrain)
    for (std::size_t i = 0; i < bodies.size(); ++i)
      if (bodies[i].moves()) jobs.emplace_back(&posed[i], &field);
  // Each sphere-tree pair's candidates, found (or made) here, before any thread runs. The
  // body pairs' jobs come first, in the order of `pairs` (by a, then b), so the cache's sorted
  // list is merged with them; ground jobs find theirs by body.
  std::vector<PairCandidates*>& memo = scratch.memo;
  memo.assign(jobs.size(), nullptr);
  if (candidates) {
    auto treeJob = [&](std::size_t k) {
      return jobs[k].first->type == ColliderType::kSphereTree &&
             jobs[k].second->type != ColliderType::kPolygon;
    };
    std::vector<std::pair<std::uint64_t, std::uint32_t>>& old = candidates->pairs;
    std::vector<std::pair<std::uint64_t, std::uint32_t>>& kept = scratch.kept;
    std::vector<PairCandidates>& slots = candidates->slots;
    std::vector<std::uint32_t>& freeSlots = candidates->freeSlots;
    kept.clear();
    std::size_t k = 0, o = 0;
    for (; k < jobs.size() && jobs[k].second->type != ColliderType::kPlane &&
           jobs[k].second->type != ColliderType::kHeightfield;
         ++k) {
      if (!treeJob(k)) continue;
      const std::uint64_t key = (static_cast<std::uint64_t>(jobs[k].first->body) << 32) |
                                static_cast<std::uint32_t>(jobs[k].second->body);
      for (; o < old.size() && old[o].first < key; ++o)  // pairs gone since: their slots freed
        freeSlots.push_back(old[o].second);
      if (o < old.size() && old[o].first == key) {
        kept.push_back(old[o++]);
      } else if (!freeSlots.empty()) {
        kept.emplace_back(key, freeSlots.back());
        freeSlots.pop_back();
        slots[kept.back().second].restart();
      } else {
        kept.emplace_back(key, static_cast<std::uint32_t>(slots.size()));
        slots.emplace_back();
      }
    }
    for (; o < old.size(); ++o) freeSlots.push_back(old[o].second);
    old.swap(kept);
    // `slots` is complete now: pointers into it stay valid for this call.
    for (std::size_t k2 = 0, p = 0; k2 < k; ++k2)
      if (treeJob(k2)) memo[k2] = &slots[old[p++].second];
    // Ground pairs by body. Only moving bodies have ground jobs: a body that does not move
    // this call (asleep, gone) starts afresh when it moves again.
    const std::size_t n = bodies.size();
    candidates->plane.resize(n);
    candidates->terrain.resize(n);
    for (; k < jobs.size(); ++k) {
      if (!treeJob(k)) continue;
      std::vector<PairCandidates>& ground =
          jobs[k].second->type == ColliderType::kPlane ? candidates->plane : candidates->terrain;
      memo[k] = &ground[static_cast<std::size_t>(jobs[k].first->body)];
    }
    for (std::size_t i = 0; i < n; ++i)
      if (!bodies[i].moves())
        for (PairCandidates* c : {&candidates->plane[i], &candidates->terrain[i]})
          if (c->holds || c->hasLast) c->restart();
  }
  // One job's contacts appended to sink, reduced if asked: each collider pair on its own, by
  // the thread that found them. A sphere tree on the plane is reduced as its contacts come
  // (PlanePatch: the same representatives, without storing every leaf contact).
  auto collideJob = [&](const Collider& a, const Collider& b, PairCandidates* m,
                        std::vector<Contact>& sink) -> std::uint64_t {
    if (!m) return collide(a, b, sink);
    if (b.type == ColliderType::kPlane) return collideTreePlane(a, b, sink, m);
    if (b.type == ColliderType::kHeightfield) return collideTreeHeightfield(a, b, sink, m);
    return TreeTreeDescent(a, b, sink, m).run();
  };
  auto run = [&](std::size_t k, std::vector<Contact>& sink, ContactCounts& counts) {
    const Collider& a = *jobs[k].first;
    const Collider& b = *jobs[k].second;
    if (reduce && a.type == ColliderType::kSphereTree && b.type == ColliderType::kPlane) {
      static thread_local PlanePatch patch;
      counts.sphereTests += collideTreePlanePatch(a, b, memo[k], patch, sink, counts.leafContacts);
      return;
    }
    const std::size_t begin = sink.size();
    counts.sphereTests += collideJob(a, b, memo[k], sink);
    counts.leafContacts += sink.size() - begin;
    if (reduce) reducePairContacts(sink, begin);
  };
  // Blocks of consecutive jobs, each into its own list, run by the pool's threads; the lists
  // are appended in block order, so the contacts are exactly the serial ones in the serial
  // order whatever the thread count. (Jobs differ in cost by orders of magnitude, a rock's pile
  // against a rock in flight: one fixed half per thread leaves one of them idle.)
  const int workers =
      pool ? std::max(
                 1, std::min<int>(pool->threads(), static_cast<int>(jobs.size() / kJobsPerThread)))
           : 1;
  ContactCounts total;
  if (workers == 1) {
    for (std::size_t k = 0; k < jobs.size(); ++k) run(k, out, total);
  } else {
    const int blocks = std::min<int>(static_cast<int>(jobs.size()), workers * kBlocksPerThread);
    std::vector<std::vector<Contact>>& found = scratch.found;
    if (found.size() < static_cast<std::size_t>(blocks)) found.resize(blocks);
    for (std::vector<Contact>& f : found) f.clear();
    std::vector<ContactCounts>& counts = scratch.counts;
    counts.assign(blocks, ContactCounts{});
    pool->run(blocks, [&](int c) {
      const std::size_t begin = jobs.size() * c / blocks, end = jobs.size() * (c + 1) / blocks;
      for (std::size_t k = begin; k < end; ++k) run(k, found[c], counts[c]);
    });
    for (int c = 0; c < blocks; ++c) {
      out.insert(out.end(), found[c].begin(), found[c].end());
      total.sphereTests += counts[c].sphereTests;
      total.leafContacts += counts[c].leafContacts;
    }
  }
  if (candidates)
    for (const PairCandidates* m : memo)
      if (m) ++(m->served ? candidates->served : candidates->descents);
  return total;
}

}  // namespace vf

// The body-body sphere-tree test of fig. 3 (against the plane and the terrain:
// tree_plane_descent.cpp, tree_terrain_descent.cpp).
//
// Bounding spheres first (the sphere circumscribing the body, not the larger
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
#include <cmath>
#include <cstdint>
#include <vector>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "sim/collide/descent_common.h"
#include "sim/shape/shape.h"

namespace vf {
namespace {

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

}  // namespace

std::uint64_t collideTreeTree(const Collider& a, const Collider& b, std::vector<Contact>& out) {
  return TreeTreeDescent(a, b, out, nullptr).run();
}

std::uint64_t collideTreeTree(const Collider& a, const Collider& b, std::vector<Contact>& out,
                              PairCandidates* memo) {
  return TreeTreeDescent(a, b, out, memo).run();
}

}  // namespace vf

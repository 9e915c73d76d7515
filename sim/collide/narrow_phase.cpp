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

struct NodeRef {
  int level;
  std::uint32_t index;
  Vec3 center;  // world for descendAlone; body a's frame in TreeTreeDescent
};

// World centre of leaf i of a sphere-tree collider, by the expression the world-frame descent
// (descendAlone) uses, so that every place that tests a leaf on its own gets the same bits (a
// one-level tree's root leaf stands at the body origin). Always inlined: GCC left it a call in
// the leaf loops, and inlining it took a Lv 6 crosses run from 1,450 to 1,320 ms (3 interleaved
// runs each).
inline __attribute__((always_inline)) Vec3 leafWorldCenter(const Collider& c, std::uint32_t i) {
  const SphereTree& tree = *c.tree;
  return tree.leafLevel() == 0 ? c.x : Vec3(c.x + c.R * tree.leaves().centers[i]);
}

// Body-body descent. The inner tests run in body a's frame: a's node centres are the tree's
// own (no transform), b's are carried into a's frame by the relative pose, so half the centre
// transforms of a world-frame descent are saved. They are widened by `slack_`, so they may let
// through a pair that the unwidened test would drop, never the reverse. A leaf pair is decided,
// and its contact computed, from world centres by the expressions a world-frame descent uses:
// the same contacts, to the bit, in the same order (the order follows the children's order, not
// the tests); every scene's checksum stayed the same.
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
    if (memo_ && planCandidates()) {  // the candidates hold: test only them
      // Most candidates of a resting pair do not touch (a leaf's neighbours within the margin
      // beside the one it touches), so each is first tested in body b's frame, widened by the
      // inner tests' rounding slack (which covers the rounding of a relative pose in either
      // body's frame as it covers a's): a pair that misses there misses exactly too. The rest
      // are decided by the leaf test itself. The descent stored a's leaf in the outer loop, so
      // runs of candidates share it: it is carried into b's frame once per run (a candidate
      // then costs a difference and a dot product), and its world centre is computed once per
      // run (the same expression, the same bits).
      const std::vector<Vec3>& centersA = ta_.leaves().centers;
      const std::vector<Vec3>& centersB = tb_.leaves().centers;
      const double reach = ta_.leaves().radius + tb_.leaves().radius + slack_;
      const Mat3 Rba = Rab_.transpose();
      const Vec3 tba = -(Rba * tab_);
      // The candidates that pass are listed first without a branch on the outcome (which
      // follows no pattern a predictor could learn), then emitted in order.
      static thread_local std::vector<std::uint32_t> pass;
      const std::vector<std::uint32_t>& leaves = memo_->leaves;
      pass.resize(leaves.size() / 2);
      std::size_t passed = 0;
      std::uint32_t lastI = UINT32_MAX;
      Vec3 inB = Vec3::Zero();
      for (std::size_t k = 0; k < leaves.size(); k += 2) {
        const std::uint32_t i = leaves[k];
        if (i != lastI) lastI = i, inB = tba + Rba * centersA[i];
        pass[passed] = static_cast<std::uint32_t>(k);
        passed += (inB - centersB[leaves[k + 1]]).squaredNorm() < reach * reach;
      }
      tests_ += leaves.size() / 2 - passed;
      lastI = UINT32_MAX;
      Vec3 wa = Vec3::Zero();
      for (std::size_t p = 0; p < passed; ++p) {
        const std::uint32_t i = leaves[pass[p]], j = leaves[pass[p] + 1];
        if (i != lastI) lastI = i, wa = leafWorldA(i);
        emit(i, wa, j, leafWorldB(j));
      }
      return tests_;
    }
    const double reach = ta_.boundingRadius + tb_.boundingRadius + slack_ + margin_;
    if ((a_.x - b_.x).squaredNorm() >= reach * reach) return tests_;
    // Level 0 is a single voxel; the bounding spheres above stand in for it.
    descend(NodeRef{0, 0, Vec3::Zero()}, NodeRef{0, 0, tab_});
    return tests_;
  }

 private:
  // Children of node n of tree a (centres as they are) or b (carried into a's frame).
  int childrenA(const NodeRef& n, std::array<NodeRef, 8>& kids) const {
    const SphereTreeLevel& lv = ta_.levels[n.level];
    const SphereTreeLevel& next = ta_.levels[n.level + 1];
    int k = 0;
    for (std::uint32_t i = lv.childBegin[n.index]; i < lv.childBegin[n.index + 1]; ++i)
      kids[k++] = NodeRef{n.level + 1, i, next.centers[i]};
    return k;
  }
  int childrenB(const NodeRef& n, std::array<NodeRef, 8>& kids) const {
    const SphereTreeLevel& lv = tb_.levels[n.level];
    const SphereTreeLevel& next = tb_.levels[n.level + 1];
    int k = 0;
    for (std::uint32_t i = lv.childBegin[n.index]; i < lv.childBegin[n.index + 1]; ++i)
      kids[k++] = NodeRef{n.level + 1, i, tab_ + Rab_ * next.centers[i]};
    return k;
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

  bool overlap(const NodeRef& na, const NodeRef& nb) {
    ++tests_;
    const double r = ta_.levels[na.level].radius + tb_.levels[nb.level].radius + slack_ + margin_;
    return (na.center - nb.center).squaredNorm() < r * r;
  }

  // na and nb may collide (or are the roots after the bounding-sphere test).
  void descend(const NodeRef& na, const NodeRef& nb) {
    const bool leafA = na.level == ta_.leafLevel();
    const bool leafB = nb.level == tb_.leafLevel();
    if (leafA && leafB) {
      emit(na.index, leafWorldA(na.index), nb.index, leafWorldB(nb.index));
      return;
    }
    std::array<NodeRef, 8> kidsA, kidsB;
    int nA = leafA ? 1 : childrenA(na, kidsA);
    int nB = leafB ? 1 : childrenB(nb, kidsB);
    if (leafA) kidsA[0] = na;
    if (leafB) kidsB[0] = nb;
    // Early exit: a child that misses the other side's node misses all that node's children
    // (they lie inside it), so it is dropped before the nA x nB child pairs are tested. The
    // order of the survivors is kept: the contacts and their order are those of the full test.
    if (!leafB && nA > 1) {
      int kept = 0;
      for (int i = 0; i < nA; ++i)
        if (overlap(kidsA[i], nb)) kidsA[kept++] = kidsA[i];
      nA = kept;
    }
    if (!leafA && nB > 1) {
      int kept = 0;
      for (int j = 0; j < nB; ++j)
        if (overlap(na, kidsB[j])) kidsB[kept++] = kidsB[j];
      nB = kept;
    }
    // Leaves among the survivors get their world centres once, for the exact test.
    const bool kidsLeafA = kidsA[0].level == ta_.leafLevel();
    const bool kidsLeafB = kidsB[0].level == tb_.leafLevel();
    std::array<Vec3, 8> wA, wB;
    if (kidsLeafA)
      for (int i = 0; i < nA; ++i) wA[i] = leafWorldA(kidsA[i].index);
    if (kidsLeafB)
      for (int j = 0; j < nB; ++j) wB[j] = leafWorldB(kidsB[j].index);
    for (int i = 0; i < nA; ++i)
      for (int j = 0; j < nB; ++j) {
        if (kidsLeafA && kidsLeafB)
          emit(kidsA[i].index, wA[i], kidsB[j].index, wB[j]);
        else if (overlap(kidsA[i], kidsB[j]))
          descend(kidsA[i], kidsB[j]);
      }
  }

  Vec3 leafWorldA(std::uint32_t i) const { return leafWorldCenter(a_, i); }
  Vec3 leafWorldB(std::uint32_t j) const { return leafWorldCenter(b_, j); }

  // The exact test of a leaf pair, and its contact, in world coordinates; while candidates
  // are built, a pair within the margin is kept as one. Always inlined into its three callers
  // (GCC kept it a call; inlined, Lv 6 crosses 1,320 -> 1,290 ms, stack 207 -> 202 ms).
  __attribute__((always_inline)) void emit(std::uint32_t leafA, const Vec3& ca, std::uint32_t leafB,
                                           const Vec3& cb) {
    ++tests_;
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
  double slack_ = 0;   // widening of the internal tests, m
  double margin_ = 0;  // while building candidates: their margin, m
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
  auto height = [&](const Vec3& c) { return p.normal.dot(c) - p.offset; };
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
    h = n.dot(center) - p.offset;
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
    PlaneServeScratch::Group G{g * kPatchGroup,
                               std::min(candidates, (g + 1) * kPatchGroup),
                               count,
                               s.member.size(),
                               true,
                               0,
                               0};
    linearRange(h0, m, memo.groupLo[g], memo.groupHi[g], G.lo, G.hi);
    G.lo -= slack, G.hi += slack;  // the rounding of the range itself
    if (G.lo >= r + slack) continue;
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
      if (count == G.first) continue;
    }
    double f1lo, f1hi, f2lo, f2hi;
    linearRange(o1, u1, memo.groupLo[g], memo.groupHi[g], f1lo, f1hi);
    linearRange(o2, u2, memo.groupLo[g], memo.groupHi[g], f2lo, f2hi);
    PatchBox box;
    box.extend(Eigen::Vector2d(f1lo - flatSlack, f2lo - flatSlack));
    box.extend(Eigen::Vector2d(f1hi + flatSlack, f2hi + flatSlack));
    s.boxes.push_back(box);
    s.groups.push_back(G);
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
// normal. Without the wall, a rock that left a raised grid onto the floor plane of the paper's
// cliff scene (or was pushed off it by a pile) met no terrain at the border and slid under the
// surface: 2-9 m deep by the true-mesh check, until the rock monitor buried it.
//
// Temporal coherence (PairCandidates; the terrain does not move, so the pair's pose is the
// body's). Why a margin bounds what a motion can change, although the leaf test is not
// Lipschitz in the centre (near a NODATA hole a centre deep below a cell is far from every
// triangle): the argument is containment, as for the plain descent. A node is dropped when its
// sphere S lies above `surfaceBoundNear` over S's footprint square, and every way a sphere s
// inside S could touch (its centre below the surface, a triangle point inside it, the border
// wall beside it) needs a surface or wall point under that bound inside the square: none. A
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
  // that is dropped without looking the cells up (the same answer, cheaper; a third of the
  // terrain narrow phase's time went into the lookups with 1,000 rocks).
  auto mayTouch = [&](const Vec3& c, double r, double& bound) {
    r += widen;
    if (c.z() - r >= bound) return false;
    bound = field.surfaceBoundNear(c.x(), c.y(), r);
    return c.z() - r < bound;
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
  const double leafRadius = tree.leaves().radius;
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
  // a step allocates nothing here once warm; for one rock on a terrain the allocations were
  // about 5 % of a step's instructions.
  struct Scratch {
    std::vector<Collider> posed;  // each active body's collider, posed once per call
    std::vector<std::pair<const Collider*, const Collider*>> jobs;
    std::vector<PairCandidates*> memo;
    std::vector<std::vector<Contact>> found;
    std::vector<ContactCounts> counts;
    std::vector<std::pair<std::uint64_t, PairCandidates>> kept;  // the cache's next pair list
  };
  static thread_local Scratch scratch;
  // Each body's collider once (a rock is in about three jobs a step, and a job holding two
  // whole colliders took 320 bytes to write and to stride over).
  std::vector<Collider>& posed = scratch.posed;
  posed.resize(bodies.size());
  for (std::size_t i = 0; i < bodies.size(); ++i) {
    if (!bodies[i].active) continue;
    const Shape& s = *bodies[i].shape;
    const int id = static_cast<int>(i);
    posed[i] = s.polyhedron ? polygonCollider(id, *s.polyhedron, states[i].x, states[i].q)
                            : sphereTreeCollider(id, *s.tree, states[i].x, states[i].q);
  }
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
    std::vector<std::pair<std::uint64_t, PairCandidates>>& old = candidates->pairs;
    std::vector<std::pair<std::uint64_t, PairCandidates>>& kept = scratch.kept;
    kept.clear();
    std::size_t k = 0, o = 0;
    for (; k < jobs.size() && jobs[k].second->type != ColliderType::kPlane &&
           jobs[k].second->type != ColliderType::kHeightfield;
         ++k) {
      if (!treeJob(k)) continue;
      const std::uint64_t key = (static_cast<std::uint64_t>(jobs[k].first->body) << 32) |
                                static_cast<std::uint32_t>(jobs[k].second->body);
      while (o < old.size() && old[o].first < key) ++o;  // pairs gone since: dropped
      if (o < old.size() && old[o].first == key)
        kept.emplace_back(key, std::move(old[o++].second));
      else
        kept.emplace_back(key, PairCandidates{});
    }
    old.swap(kept);  // complete now: pointers into it stay valid for this call
    for (std::size_t k2 = 0, p = 0; k2 < k; ++k2)
      if (treeJob(k2)) memo[k2] = &old[p++].second;
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
          if (c->holds || c->hasLast) *c = PairCandidates{};
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
  // against a rock in flight: one fixed half per thread left one of them idle.)
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

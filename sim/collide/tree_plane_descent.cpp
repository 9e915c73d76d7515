// Sphere tree against the floor plane: fig. 3's descent of one tree, with the plane's exact
// sphere test, stored whole or reduced as the contacts come (PlanePatch).
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <type_traits>
#include <vector>

#include "sim/collide/contact_reduction.h"
#include "sim/collide/descent_common.h"
#include "sim/shape/shape.h"

namespace vf {
namespace {

// Freshly built candidates' groups' bounds, for servePlanePatch: the body-frame box of the
// centres of each group of kPatchGroup consecutive candidates.
void boundCandidateGroups(const SphereTree& tree, PairCandidates& memo) {
  const std::vector<Vec3>& centers = tree.leaves().centers;
  const std::size_t groups = (memo.leaves.size() + kPatchGroup - 1) / kPatchGroup;
  memo.groupLo.assign(groups, Vec3::Constant(INFINITY));
  memo.groupHi.assign(groups, Vec3::Constant(-INFINITY));
  for (std::size_t k = 0; k < memo.leaves.size(); ++k) {
    const Vec3& c = centers[memo.leaves[k]];
    memo.groupLo[k / kPatchGroup] = memo.groupLo[k / kPatchGroup].cwiseMin(c);
    memo.groupHi[k / kPatchGroup] = memo.groupHi[k / kPatchGroup].cwiseMax(c);
  }
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
  if (margin > 0) boundCandidateGroups(tree, *memo);
  return tests;
}

}  // namespace

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

}  // namespace vf

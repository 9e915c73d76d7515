// A body's plane contacts reduced straight from its candidates while they hold
// (servePlanePatch, called by collideTreePlanePatch in tree_plane_descent.cpp).
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "sim/collide/contact_reduction.h"
#include "sim/collide/descent_common.h"

namespace vf {
namespace {

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

}  // namespace

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

}  // namespace vf

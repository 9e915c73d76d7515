// A body's plane contacts reduced straight from its candidates while they hold
// (servePlanePatch, called by collideTreePlanePatch in tree_plane_descent.cpp).
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "sim/collide/contact_reduction.h"
#include "sim/collide/descent_common.h"
#include "sim/shape/shape.h"

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

// One call of servePlanePatch: the body, the plane, the candidates and the frames their
// heights and plane coordinates are taken in.
class PlaneServe {
 public:
  PlaneServe(const Collider& a, const Collider& p, const PairCandidates& memo, double h0,
             const Vec3& m, double slack, PlaneServeScratch& s)
      : a_(a),
        p_(p),
        memo_(memo),
        h0_(h0),
        m_(m),
        slack_(slack),
        s_(s),
        centers_(a.tree->leaves().centers),
        r_(a.tree->leaves().radius),
        n_(p.normal) {
    const SphereTree& tree = *a.tree;
    patchPlaneBasis(n_, t1_, t2_);
    u1_ = a.R.transpose() * t1_;
    u2_ = a.R.transpose() * t2_;
    o1_ = a.x.dot(t1_);
    o2_ = a.x.dot(t2_);
    flatSlack_ =
        1e-9 * (1 + a.x.norm() + 2 * tree.boundingRadius + std::abs(p.offset) + std::abs(h0));
  }

  // Sorts the candidates' groups into those without contacts (dropped), those whose every
  // candidate is one and the mixed ones, whose contacts are listed; bounds each kept group's
  // plane coordinates. Returns the number of contacts; lowestUpper: at least the lowest
  // body-frame height of a contact.
  std::size_t classifyGroups(double& lowestUpper) {
    const std::size_t candidates = memo_.leaves.size();
    s_.groups.clear();
    s_.member.clear();
    s_.boxes.clear();
    std::size_t count = 0;
    lowestUpper = INFINITY;
    for (std::size_t g = 0; g * kPatchGroup < candidates; ++g) {
      // Written in place and dropped where it holds no contact: built on the stack and copied,
      // it costs the copy's loads a stalled store forwarding each (perf annotate).
      PlaneServeScratch::Group& G = s_.groups.emplace_back();
      G.begin = g * kPatchGroup;
      G.end = std::min(candidates, (g + 1) * kPatchGroup);
      G.first = count;
      G.members = s_.member.size();
      G.all = true;
      linearRange(h0_, m_, memo_.groupLo[g], memo_.groupHi[g], G.lo, G.hi);
      G.lo -= slack_, G.hi += slack_;  // the rounding of the range itself
      if (G.lo >= r_ + slack_) {
        s_.groups.pop_back();
        continue;
      }
      if (G.hi < r_ - slack_) {
        count += G.end - G.begin;
        lowestUpper = std::min(lowestUpper, G.hi);
      } else if (!listMembers(G, count, lowestUpper)) {
        s_.groups.pop_back();
        continue;
      }
      double f1lo, f1hi, f2lo, f2hi;
      linearRange(o1_, u1_, memo_.groupLo[g], memo_.groupHi[g], f1lo, f1hi);
      linearRange(o2_, u2_, memo_.groupLo[g], memo_.groupHi[g], f2lo, f2hi);
      PatchBox box;
      box.extend(Eigen::Vector2d(f1lo - flatSlack_, f2lo - flatSlack_));
      box.extend(Eigen::Vector2d(f1hi + flatSlack_, f2hi + flatSlack_));
      s_.boxes.push_back(box);
    }
    return count;
  }

  // Sizes the per-contact lists for `count` contacts and marks every group unfilled.
  void prepare(std::size_t count) {
    if (s_.flat.size() < count) {  // grown, never shrunk: no clearing per call
      s_.flat.resize(count);
      s_.point.resize(count);
      s_.depth.resize(count);
      s_.leaf.resize(count);
    }
    s_.groupBegin.resize(s_.groups.size() + 1);
    for (std::size_t g = 0; g < s_.groups.size(); ++g) s_.groupBegin[g] = s_.groups[g].first;
    s_.groupBegin[s_.groups.size()] = count;
    s_.filled.assign(s_.groups.size(), 0);
  }

  // A patch of at most kContactsPerPatch contacts: all of them, deepest first.
  void emitWhole(std::size_t count, std::vector<Contact>& out) {
    for (std::size_t g = 0; g < s_.groups.size(); ++g) fill(g);
    std::size_t order[kContactsPerPatch];
    deepestFirst(s_.depth.data(), count, order);
    for (std::size_t j = 0; j < count; ++j) contact(order[j], out);
  }

  // A larger patch: its representatives, from the deepest contact and the groups' boxes.
  void emitRepresentatives(std::size_t count, double lowestUpper, std::vector<Contact>& out) {
    const std::size_t deepest = findDeepest(count, lowestUpper);
    std::size_t keep[kContactsPerPatch];
    // (A std::function holding only a pointer stays in its small buffer: no allocation.)
    PlaneServe* self = this;
    const int kept = chooseRepresentatives(
        count, deepest, s_.flat.data(), s_.boxes.data(), s_.groupBegin.data(), s_.groups.size(),
        [self](std::size_t g) { self->fill(g); }, keep);
    for (int k = 0; k < kept; ++k) contact(keep[k], out);
  }

 private:
  // Group G, whose body-frame heights straddle r: each candidate decides, by its body-frame
  // height, and by its exact test where that lies within slack of r. Lists its contacts in
  // member; returns whether it has any.
  bool listMembers(PlaneServeScratch::Group& G, std::size_t& count, double& lowestUpper) {
    G.all = false;
    for (std::size_t k = G.begin; k < G.end; ++k) {
      const double hb = bodyHeight(k);
      if (!(hb < r_ - slack_)) {
        if (hb >= r_ + slack_) continue;
        Vec3 point;
        double h;
        exact(memo_.leaves[k], point, h);
        if (!(h < r_)) continue;
      }
      s_.member.push_back(k);
      lowestUpper = std::min(lowestUpper, hb);
      ++count;
    }
    return count != G.first;
  }

  // The deepest contact: the lowest body-frame height of a contact, in the groups that may
  // hold it, then the exact depths of the contacts within 3 slack of it, the first of the
  // largest.
  std::size_t findDeepest(std::size_t count, double lowestUpper) {
    const double reach = lowestUpper + 3 * slack_;
    double lowest = INFINITY;
    for (std::size_t g = 0; g < s_.groups.size(); ++g) {
      const PlaneServeScratch::Group& G = s_.groups[g];
      if (G.lo > reach) continue;
      for (std::size_t j = G.first; j < s_.groupBegin[g + 1]; ++j)
        lowest = std::min(lowest, bodyHeight(candidateOf(G, j)));
    }
    std::size_t deepest = count;
    for (std::size_t g = 0; g < s_.groups.size(); ++g) {
      const PlaneServeScratch::Group& G = s_.groups[g];
      if (G.lo > lowest + 3 * slack_) continue;
      for (std::size_t j = G.first; j < s_.groupBegin[g + 1]; ++j) {
        if (bodyHeight(candidateOf(G, j)) > lowest + 3 * slack_) continue;
        fill(g);
        if (deepest == count || s_.depth[j] > s_.depth[deepest]) deepest = j;
      }
    }
    return deepest;
  }

  // The exact values of leaf i, by treePlaneDescent's expressions.
  void exact(std::uint32_t i, Vec3& point, double& h) const {
    const Vec3 center = leafWorldCenter(a_, i);
    h = planeHeight(p_, center);
    point = center - h * n_;
  }
  double bodyHeight(std::size_t k) const { return h0_ + m_.dot(centers_[memo_.leaves[k]]); }
  // The candidate index of contact j of group G.
  std::size_t candidateOf(const PlaneServeScratch::Group& G, std::size_t j) const {
    return G.all ? G.begin + (j - G.first) : s_.member[G.members + (j - G.first)];
  }
  // Group g's contacts' exact values, once.
  void fill(std::size_t g) {
    if (s_.filled[g]) return;
    s_.filled[g] = 1;
    const PlaneServeScratch::Group& G = s_.groups[g];
    for (std::size_t j = G.first; j < s_.groupBegin[g + 1]; ++j) {
      const std::uint32_t i = memo_.leaves[candidateOf(G, j)];
      double h;
      exact(i, s_.point[j], h);
      s_.leaf[j] = i;
      s_.depth[j] = r_ - h;
      s_.flat[j] = Eigen::Vector2d(s_.point[j].dot(t1_), s_.point[j].dot(t2_));
    }
  }
  void contact(std::size_t j, std::vector<Contact>& out) const {
    Contact c;
    c.a = a_.body;
    c.b = p_.body;
    c.point = s_.point[j];
    c.normal = n_;
    c.depth = s_.depth[j];
    c.leafA = s_.leaf[j];
    out.push_back(c);
  }

  const Collider& a_;
  const Collider& p_;
  const PairCandidates& memo_;
  const double h0_;
  const Vec3& m_;
  const double slack_;
  PlaneServeScratch& s_;
  const std::vector<Vec3>& centers_;  // the leaves' body-frame centres
  const double r_;                    // the leaf radius
  const Vec3& n_;                     // the plane's normal
  Vec3 t1_, t2_;                      // the patch plane's basis (patchPlaneBasis)
  Vec3 u1_, u2_;                      // t1_, t2_ in the body frame
  double o1_ = 0, o2_ = 0;            // the body origin's plane coordinates
  double flatSlack_ = 0;              // the bound on the rounding of o + u.c
};

}  // namespace

std::uint64_t servePlanePatch(const Collider& a, const Collider& p, const PairCandidates& memo,
                              double h0, const Vec3& m, double slack, std::vector<Contact>& out,
                              std::uint64_t& leafContacts) {
  static thread_local PlaneServeScratch s;
  PlaneServe serve(a, p, memo, h0, m, slack, s);
  double lowestUpper;
  const std::size_t count = serve.classifyGroups(lowestUpper);
  leafContacts += count;
  const std::size_t candidates = memo.leaves.size();
  if (count == 0) return candidates;
  serve.prepare(count);
  if (count <= static_cast<std::size_t>(kContactsPerPatch))
    serve.emitWhole(count, out);
  else
    serve.emitRepresentatives(count, lowestUpper, out);
  return candidates;
}

}  // namespace vf

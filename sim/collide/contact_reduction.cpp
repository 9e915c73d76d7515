// Why: a face resting on a face yields one leaf contact per overlapping leaf-sphere pair, about
// 40 per pair at level 4 and four times more per level, and the sequential-impulse solver
// spends 65-96 % of a step on piles visiting them 12 times each. The solution of the contact
// problem of one flat patch depends on where the patch's support is (the convex hull of its
// contact points) and on its normal, not on how many points fill it, so a few points that span
// the patch carry the same impulse (the solver distributes it over them, as it would over all
// the leaf contacts).
//
// Per body pair:
//  1. Patches: contacts are taken in narrow-phase order; each joins the first patch whose first
//     contact's normal is within 60 degrees of its own, else starts a new one. Leaf-sphere normals
//     of one flat patch tilt by up to 45 degrees (centre-to-centre directions of voxels), while the
//     faces of an interlocking non-convex pair (the crosses) meet at 90 degrees and stay apart.
//  2. A patch of at most kContactsPerPatch contacts is kept as it is (its own normals): a single
//     contact is exactly eq. 15.
//  3. A larger patch keeps: its deepest contact; the one farthest from it; the one that
//     maximises the triangle area with these two; the one farthest outside that triangle, all
//     measured in the plane of the patch normal. The four carry the patch normal (depth-weighted
//     mean of the leaf normals, so the tilts of the individual leaf pairs cancel as they do
//     when all are solved; when every contact carries the same normal, as on a plane, that
//     normal itself) and their own point and depth.
// Ties are broken by the narrow phase's order (a fixed order), and a kept contact keeps its
// leaf keys, so warm starting still finds it in the next step while the patch persists.
// Alternatives rejected: averaging all points of a patch into one contact (loses the support
// polygon: a block would rock on its centre), and keeping a fixed budget per pair regardless
// of normals (the two faces of an interlocked cross would share one averaged normal).
#include "sim/collide/contact_reduction.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <functional>

namespace vf {
namespace {

constexpr double kSamePatchCos = 0.5;  // cos 60 degrees

double cross2(const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  return a.x() * b.y() - a.y() * b.x();
}

// The patch normal: the depth-weighted sum of the leaf normals, normalised (`first`, the
// patch's first normal, if the sum vanishes); `first` itself when every contact of the patch
// carries it (a sphere tree on a plane: the mean of equal unit vectors is that vector, and
// summing would only add rounding; for an axis-aligned plane it is the same bits either way).
Vec3 patchNormal(const Vec3& sum, const Vec3& first, bool allFirst) {
  if (allFirst) return first;
  return sum.norm() > 0 ? Vec3(sum.normalized()) : first;
}

// The range [lo, hi] over a box of the signed area cross2(e, p - q) (linear in p: its extremes
// are at corners), widened by far more than the rounding of any of its evaluations in the box
// (relative 1e-9 of the sizes of its two products), so that every computed value at a point in
// the box lies inside.
void crossRange(const Eigen::Vector2d& e, const Eigen::Vector2d& q, const PatchBox& b, double& lo,
                double& hi) {
  const double dx0 = b.x0 - q.x(), dx1 = b.x1 - q.x(), dy0 = b.y0 - q.y(), dy1 = b.y1 - q.y();
  const double c00 = e.x() * dy0 - e.y() * dx0, c01 = e.x() * dy1 - e.y() * dx0;
  const double c10 = e.x() * dy0 - e.y() * dx1, c11 = e.x() * dy1 - e.y() * dx1;
  const double slack = 1e-9 * (std::abs(e.x()) * std::max(std::abs(dy0), std::abs(dy1)) +
                               std::abs(e.y()) * std::max(std::abs(dx0), std::abs(dx1)));
  lo = std::min(std::min(c00, c01), std::min(c10, c11)) - slack;
  hi = std::max(std::max(c00, c01), std::max(c10, c11)) + slack;
}

// The largest squared distance from q of a point in the box, as computed: rounding is
// monotone, so no point's computed (p - q).squaredNorm() exceeds the one computed from the
// farther sides (the factor is a margin on top).
double farthestBound(const Eigen::Vector2d& q, const PatchBox& b) {
  const double dx = std::max(std::abs(b.x0 - q.x()), std::abs(b.x1 - q.x()));
  const double dy = std::max(std::abs(b.y0 - q.y()), std::abs(b.y1 - q.y()));
  return (dx * dx + dy * dy) * (1 + 1e-12);
}

// Chooses the representatives of a patch of m > kContactsPerPatch points with their plane
// coordinates in `flat` and `boxes` (as for chooseRepresentatives); `points`' coordinates are
// computed here, every group filled.
int spanningSubset(const Vec3* points, std::size_t m, std::size_t deepest, const Vec3& n,
                   std::vector<Eigen::Vector2d>& flat, std::vector<PatchBox>& boxes,
                   std::vector<std::size_t>& groupBegin, std::size_t keep[kContactsPerPatch]) {
  Vec3 t1, t2;
  patchPlaneBasis(n, t1, t2);
  flat.resize(m);
  boxes.resize((m + kPatchGroup - 1) / kPatchGroup);
  groupBegin.resize(boxes.size() + 1);
  for (std::size_t g = 0; g <= boxes.size(); ++g) groupBegin[g] = std::min(m, g * kPatchGroup);
  for (std::size_t g = 0; g < boxes.size(); ++g) {
    PatchBox box;  // in registers while its group is read
    const std::size_t end = std::min(m, (g + 1) * kPatchGroup);
    for (std::size_t k = g * kPatchGroup; k < end; ++k) {
      flat[k] = Eigen::Vector2d(points[k].dot(t1), points[k].dot(t2));
      box.extend(flat[k]);
    }
    boxes[g] = box;
  }
  return chooseRepresentatives(m, deepest, flat.data(), boxes.data(), groupBegin.data(),
                               boxes.size(), nullptr, keep);
}

// Scratch space reused over the pairs of one thread, so that a step allocates once, not per
// pair and patch (at level 6 a step has thousands of leaf contacts in a few pairs).
struct Scratch {
  std::vector<int> patchOf;           // patch of each contact of the pair, in narrow-phase order
  std::vector<int> heads;             // first contact of each patch (its normal decides membership)
  std::vector<Vec3> sums;             // each patch's sum of max(depth, 0) * normal
  std::vector<int> members;           // the contacts of the patch being reduced, in order
  std::vector<Vec3> points;           // their points
  std::vector<Eigen::Vector2d> flat;  // their points in the patch plane
  std::vector<PatchBox> boxes;        // and the boxes of groups of them,
  std::vector<std::size_t> groupBegin;  // where each group begins
  std::vector<Contact> kept;            // the pair's output, before it is written back in place
};

// The representatives of one pair's contacts cs[begin, end) into s.kept.
void reducePair(const std::vector<Contact>& cs, std::size_t begin, std::size_t end, Scratch& s) {
  // Patches in narrow-phase order: a contact joins the first patch whose first contact's normal
  // is within 60 degrees of its own. Each patch's depth-weighted normal sum is accumulated on the
  // way, in the patch's order.
  // The sum of the patch that took the last contact is kept in `running` (consecutive contacts
  // mostly share a patch) and stored when another patch takes one: the same additions in the
  // same order, without a store and reload of the sum per contact.
  s.heads.clear();
  s.sums.clear();
  s.patchOf.resize(end - begin);
  std::size_t current = 0;
  Vec3 running = Vec3::Zero();
  for (std::size_t i = begin; i < end; ++i) {
    const Contact& c = cs[i];
    std::size_t k = 0;
    while (k < s.heads.size() && cs[s.heads[k]].normal.dot(c.normal) < kSamePatchCos) ++k;
    if (k == s.heads.size()) {
      s.heads.push_back(static_cast<int>(i));
      s.sums.push_back(Vec3::Zero());
    }
    if (k != current) {
      s.sums[current] = running;
      running = s.sums[k];
      current = k;
    }
    s.patchOf[i - begin] = static_cast<int>(k);
    running += std::max(c.depth, 0.0) * c.normal;
  }
  s.sums[current] = running;
  s.kept.clear();
  for (std::size_t k = 0; k < s.heads.size(); ++k) {
    s.members.clear();
    if (s.heads.size() == 1) {
      for (std::size_t i = begin; i < end; ++i) s.members.push_back(static_cast<int>(i));
    } else {
      for (std::size_t i = begin; i < end; ++i)
        if (s.patchOf[i - begin] == static_cast<int>(k)) s.members.push_back(static_cast<int>(i));
    }
    if (static_cast<int>(s.members.size()) <= kContactsPerPatch) {
      std::stable_sort(s.members.begin(), s.members.end(),
                       [&](int x, int y) { return cs[x].depth > cs[y].depth; });
      for (int i : s.members) s.kept.push_back(cs[i]);
      continue;
    }
    const std::size_t m = s.members.size();
    s.points.resize(m);
    std::size_t deepest = 0;
    const Vec3& first = cs[s.members[0]].normal;
    bool allFirst = true;
    for (std::size_t j = 0; j < m; ++j) {
      const Contact& c = cs[s.members[j]];
      s.points[j] = c.point;
      allFirst = allFirst && c.normal == first;
      if (c.depth > cs[s.members[deepest]].depth) deepest = j;  // ties: narrow-phase order
    }
    const Vec3 n = patchNormal(s.sums[k], first, allFirst);
    std::size_t keep[kContactsPerPatch];
    const int kept =
        spanningSubset(s.points.data(), m, deepest, n, s.flat, s.boxes, s.groupBegin, keep);
    for (int j = 0; j < kept; ++j) {
      Contact c = cs[s.members[keep[j]]];
      c.normal = n;
      s.kept.push_back(c);
    }
  }
}

Scratch& scratch() {
  static thread_local Scratch s;  // per thread: the narrow phase's workers reduce their pairs
  return s;
}

}  // namespace

void deepestFirst(const double* depths, std::size_t m, std::size_t order[kContactsPerPatch]) {
  for (std::size_t k = 0; k < m; ++k) order[k] = k;
  std::stable_sort(order, order + m,
                   [&](std::size_t x, std::size_t y) { return depths[x] > depths[y]; });
}

void patchPlaneBasis(const Vec3& n, Vec3& t1, Vec3& t2) {
  t1 = (std::abs(n.x()) < 0.57 ? Vec3::UnitX() : Vec3::UnitY()).cross(n).normalized();
  t2 = n.cross(t1);
}

int chooseRepresentatives(std::size_t m, std::size_t deepest, const Eigen::Vector2d* flat,
                          const PatchBox* boxes, const std::size_t* groupBegin, std::size_t groups,
                          const std::function<void(std::size_t)>& fill,
                          std::size_t keep[kContactsPerPatch]) {
  auto ensure = [&](std::size_t g) {
    if (fill) fill(g);
  };
  const Eigen::Vector2d p0 = flat[deepest];
  keep[0] = deepest;
  keep[1] = keep[2] = keep[3] = m;
  int kept = 1;
  // The point (not kept yet) with the largest positive score, or m if none scores > 0; ties go
  // to the first in narrow-phase order. `bound(box)` is at least the score of every point in
  // the box as computed, so a group whose bound is below the best score so far holds no point
  // that would replace it (nor one that ties, at its bound, with a later one): skipping it gives
  // the full scan's answer, bit for bit. The group with the largest bound is scanned first, so
  // that the best score is near its final value before the others are looked at (lazily filled
  // groups cost exact values; the narrow phase gives a patch's points in sphere-tree order, so
  // a group is a small cluster and few groups reach the extremes these scores look for).
  static thread_local std::vector<double> bounds;
  bounds.resize(groups);
  auto best = [&](auto score, auto bound) {
    std::size_t first = groups;
    for (std::size_t g = 0; g < groups; ++g) {
      bounds[g] = bound(boxes[g]);
      if (bounds[g] > 0 && (first == groups || bounds[g] > bounds[first])) first = g;
    }
    std::size_t arg = m;
    double top = 0;
    auto scan = [&](std::size_t g) {
      ensure(g);
      for (std::size_t k = groupBegin[g]; k < groupBegin[g + 1]; ++k) {
        const double sc = score(flat[k]);
        if ((sc > top || (sc == top && sc > 0 && k < arg)) && k != keep[0] && k != keep[1] &&
            k != keep[2])
          top = sc, arg = k;
      }
    };
    if (first == groups) return arg;  // no point scores above zero
    scan(first);
    for (std::size_t g = 0; g < groups; ++g) {
      if (g == first || bounds[g] < top || (bounds[g] == top && groupBegin[g] > arg)) continue;
      scan(g);
    }
    return arg;
  };
  // The farthest from the deepest.
  const std::size_t i1 = best([&](const Eigen::Vector2d& p) { return (p - p0).squaredNorm(); },
                              [&](const PatchBox& b) { return farthestBound(p0, b); });
  if (i1 < m) {
    keep[kept++] = i1;
    const Eigen::Vector2d p1 = flat[i1];
    const Eigen::Vector2d e = p1 - p0;
    // The largest triangle with these two.
    const std::size_t i2 =
        best([&](const Eigen::Vector2d& p) { return std::abs(cross2(e, p - p0)); },
             [&](const PatchBox& b) {
               double lo, hi;
               crossRange(e, p0, b, lo, hi);
               return std::max(std::abs(lo), std::abs(hi));
             });
    if (i2 < m) {
      keep[kept++] = i2;
      const Eigen::Vector2d p2 = flat[i2];
      // Farthest outside the triangle: the largest area added beyond one of its edges.
      const double side = cross2(p1 - p0, p2 - p0) > 0 ? 1.0 : -1.0;
      const Eigen::Vector2d e0 = p1 - p0, e1 = p2 - p1, e2 = p0 - p2;  // the triangle's edges
      const std::size_t i3 = best(
          [&](const Eigen::Vector2d& p) {
            return -side *
                   std::min(std::min(cross2(e0, p - p0), cross2(e1, p - p1)), cross2(e2, p - p2));
          },
          [&](const PatchBox& b) {
            // side > 0: -min(c) is at most -min(lo); side < 0: min(c) is at most min(hi).
            double lo[3], hi[3];
            crossRange(e0, p0, b, lo[0], hi[0]);
            crossRange(e1, p1, b, lo[1], hi[1]);
            crossRange(e2, p2, b, lo[2], hi[2]);
            return side > 0 ? -std::min(std::min(lo[0], lo[1]), lo[2])
                            : std::min(std::min(hi[0], hi[1]), hi[2]);
          });
      if (i3 < m) keep[kept++] = i3;
    }
  }
  return kept;
}

void reducePairContacts(std::vector<Contact>& contacts, std::size_t begin) {
  if (contacts.size() - begin <= 1) return;  // nothing to choose
  Scratch& s = scratch();
  reducePair(contacts, begin, contacts.size(), s);
  // A pair's representatives are no more than its contacts.
  std::copy(s.kept.begin(), s.kept.end(), contacts.begin() + static_cast<std::ptrdiff_t>(begin));
  contacts.resize(begin + s.kept.size());
}

void reduceContacts(std::vector<Contact>& contacts) {
  // In place: a pair's representatives are no more than its contacts, so they are written at or
  // before where the pair began, after all of its contacts have been read.
  Scratch& s = scratch();
  std::size_t write = 0;
  for (std::size_t begin = 0; begin < contacts.size();) {
    std::size_t end = begin + 1;
    while (end < contacts.size() && contacts[end].a == contacts[begin].a &&
           contacts[end].b == contacts[begin].b)
      ++end;
    reducePair(contacts, begin, end, s);
    for (const Contact& c : s.kept) contacts[write++] = c;
    begin = end;
  }
  contacts.resize(write);
}

void PlanePatch::start(const Vec3& normal) {
  normal_ = normal;
  points_.clear();
  depths_.clear();
  leaves_.clear();
}

void PlanePatch::finish(int a, int b, std::vector<Contact>& out) {
  const std::size_t m = points_.size();
  auto contact = [&](std::size_t k, const Vec3& n) {
    Contact c;
    c.a = a;
    c.b = b;
    c.point = points_[k];
    c.normal = n;
    c.depth = depths_[k];
    c.leafA = leaves_[k];
    out.push_back(c);
  };
  if (m <= static_cast<std::size_t>(kContactsPerPatch)) {  // as they are, deepest first
    std::size_t order[kContactsPerPatch];
    deepestFirst(depths_.data(), m, order);
    for (std::size_t k = 0; k < m; ++k) contact(order[k], normal_);
    return;
  }
  // Every contact carries the plane's normal, which is then the patch normal (patchNormal),
  // and the first of the deepest contacts.
  std::size_t deepest = 0;
  for (std::size_t k = 0; k < m; ++k)
    if (depths_[k] > depths_[deepest]) deepest = k;
  const Vec3& n = normal_;
  std::size_t keep[kContactsPerPatch];
  Scratch& s = scratch();
  const int kept =
      spanningSubset(points_.data(), m, deepest, n, s.flat, s.boxes, s.groupBegin, keep);
  for (int k = 0; k < kept; ++k) contact(keep[k], n);
}

}  // namespace vf

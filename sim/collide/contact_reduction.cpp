// Why: a face resting on a face yields one leaf contact per overlapping leaf-sphere pair, about
// 40 per pair at level 4 and four times more per level, and the sequential-impulse solver
// spends 65-96 % of a step on piles visiting them 12 times each. The solution of the contact
// problem of one flat patch depends on where the patch's support is (the convex hull of its
// contact points) and on its normal, not on how many points fill it, so a few points that span
// the patch carry the same impulse (the solver distributes it over them, as it distributed it
// over all leaf contacts before).
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
//     mean of the leaf normals, so the tilts of the individual leaf pairs cancel as they did
//     when all were solved) and their own point and depth.
// Ties are broken by the narrow phase's order (a fixed order), and a kept contact keeps its
// leaf keys, so warm starting still finds it in the next step while the patch persists.
// Alternatives rejected: averaging all points of a patch into one contact (loses the support
// polygon: a block would rock on its centre), and keeping a fixed budget per pair regardless
// of normals (the two faces of an interlocked cross would share one averaged normal).
#include "sim/collide/contact_reduction.h"

#include <algorithm>
#include <cmath>

namespace vf {
namespace {

constexpr double kSamePatchCos = 0.5;  // cos 60 degrees

// Indices into `cs` of the representatives of one patch (size > kContactsPerPatch), in the
// order chosen; `n` is the patch normal. Points are compared in 2-D coordinates of the patch
// plane, computed once.
std::vector<int> spanningSubset(const std::vector<Contact>& cs, const std::vector<int>& patch,
                                const Vec3& n) {
  Vec3 t1, t2;  // any basis of the plane: only distances and areas in it matter
  t1 = (std::abs(n.x()) < 0.57 ? Vec3::UnitX() : Vec3::UnitY()).cross(n).normalized();
  t2 = n.cross(t1);
  const std::size_t m = patch.size();
  std::vector<Eigen::Vector2d> flat(m);
  std::size_t deepest = 0;
  for (std::size_t k = 0; k < m; ++k) {
    const Vec3& p = cs[patch[k]].point;
    flat[k] = Eigen::Vector2d(p.dot(t1), p.dot(t2));
    if (cs[patch[k]].depth > cs[patch[deepest]].depth) deepest = k;  // ties: narrow-phase order
  }
  std::vector<std::size_t> keep{deepest};
  // The contact (not kept yet) with the largest positive score, or m if none scores > 0.
  auto best = [&](auto score) {
    std::size_t arg = m;
    double top = 0;
    for (std::size_t k = 0; k < m; ++k) {
      if (std::find(keep.begin(), keep.end(), k) != keep.end()) continue;
      const double sc = score(flat[k]);
      if (sc > top) top = sc, arg = k;
    }
    return arg;
  };
  auto cross2 = [](const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
    return a.x() * b.y() - a.y() * b.x();
  };
  const Eigen::Vector2d p0 = flat[deepest];
  const std::size_t i1 = best([&](const Eigen::Vector2d& p) { return (p - p0).squaredNorm(); });
  if (i1 < m) {
    keep.push_back(i1);
    const Eigen::Vector2d p1 = flat[i1];
    const std::size_t i2 =
        best([&](const Eigen::Vector2d& p) { return std::abs(cross2(p1 - p0, p - p0)); });
    if (i2 < m) {
      keep.push_back(i2);
      const Eigen::Vector2d p2 = flat[i2];
      // Farthest outside the triangle: the largest area added beyond one of its edges.
      const double side = cross2(p1 - p0, p2 - p0) > 0 ? 1.0 : -1.0;
      const std::size_t i3 = best([&](const Eigen::Vector2d& p) {
        return -side * std::min({cross2(p1 - p0, p - p0), cross2(p2 - p1, p - p1),
                                 cross2(p0 - p2, p - p2)});
      });
      if (i3 < m) keep.push_back(i3);
    }
  }
  std::vector<int> out;
  for (std::size_t k : keep) out.push_back(patch[k]);
  return out;
}

void reducePair(const std::vector<Contact>& cs, std::size_t begin, std::size_t end,
                std::vector<Contact>& out) {
  // Patches in narrow-phase order: a contact joins the first patch whose first contact's normal
  // is within 60 degrees of its own.
  std::vector<std::vector<int>> patches;
  for (std::size_t i = begin; i < end; ++i) {
    std::size_t k = 0;
    while (k < patches.size() && cs[patches[k][0]].normal.dot(cs[i].normal) < kSamePatchCos) ++k;
    if (k == patches.size()) patches.emplace_back();
    patches[k].push_back(static_cast<int>(i));
  }
  for (std::vector<int>& patch : patches) {
    if (static_cast<int>(patch.size()) <= kContactsPerPatch) {
      std::stable_sort(patch.begin(), patch.end(),
                       [&](int x, int y) { return cs[x].depth > cs[y].depth; });
      for (int i : patch) out.push_back(cs[i]);
      continue;
    }
    Vec3 sum = Vec3::Zero();
    for (int i : patch) sum += std::max(cs[i].depth, 0.0) * cs[i].normal;
    const Vec3 n = sum.norm() > 0 ? Vec3(sum.normalized()) : cs[patch[0]].normal;
    for (int i : spanningSubset(cs, patch, n)) {
      Contact c = cs[i];
      c.normal = n;
      out.push_back(c);
    }
  }
}

}  // namespace

void reduceContacts(std::vector<Contact>& contacts) {
  std::vector<Contact> out;
  out.reserve(contacts.size());
  for (std::size_t begin = 0; begin < contacts.size();) {
    std::size_t end = begin + 1;
    while (end < contacts.size() && contacts[end].a == contacts[begin].a &&
           contacts[end].b == contacts[begin].b)
      ++end;
    reducePair(contacts, begin, end, out);
    begin = end;
  }
  contacts.swap(out);
}

}  // namespace vf

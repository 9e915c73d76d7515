// Why: a face resting on a face yields one leaf contact per overlapping leaf-sphere pair, about
// 40 per pair at level 4 and four times more per level, and the sequential-impulse solver
// spends 65-96 % of a step on piles visiting them 12 times each. The solution of the contact
// problem of one flat patch depends on where the patch's support is (the convex hull of its
// contact points) and on its normal, not on how many points fill it, so a few points that span
// the patch carry the same impulse (the solver distributes it over them, as it distributed it
// over all leaf contacts before).
//
// Per body pair:
//  1. Patches: contacts are taken deepest first; each joins the first patch whose normal is
//     within 60 degrees of its own, else starts a new one. Leaf-sphere normals of one flat
//     patch tilt by up to 45 degrees (centre-to-centre directions of voxels), while the faces of
//     an interlocking non-convex pair (the crosses) meet at 90 degrees and stay apart.
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
#include <numeric>

namespace vf {
namespace {

constexpr double kSamePatchCos = 0.5;  // cos 60 degrees

// Indices into `cs` of the representatives of one patch (size > kContactsPerPatch), in the
// order chosen; `n` is the patch normal.
std::vector<int> spanningSubset(const std::vector<Contact>& cs, const std::vector<int>& patch,
                                const Vec3& n) {
  auto flat = [&](int i) {  // point projected into the patch plane
    const Vec3& p = cs[i].point;
    return Vec3(p - n.dot(p) * n);
  };
  std::vector<int> keep;
  // Deepest (patch is sorted deepest first, ties in narrow-phase order).
  keep.push_back(patch[0]);
  const Vec3 p0 = flat(patch[0]);
  auto best = [&](auto score) {
    int arg = -1;
    double top = 0;
    for (int i : patch) {
      if (std::find(keep.begin(), keep.end(), i) != keep.end()) continue;
      const double s = score(flat(i));
      if (s > top) top = s, arg = i;
    }
    return arg;
  };
  const int i1 = best([&](const Vec3& p) { return (p - p0).squaredNorm(); });
  if (i1 < 0) return keep;
  keep.push_back(i1);
  const Vec3 p1 = flat(i1);
  const int i2 = best([&](const Vec3& p) { return (p1 - p0).cross(p - p0).squaredNorm(); });
  if (i2 < 0) return keep;
  keep.push_back(i2);
  const Vec3 p2 = flat(i2);
  // Farthest outside the triangle: largest area added on the far side of one of its edges.
  const Vec3 triN = (p1 - p0).cross(p2 - p0);
  const int i3 = best([&](const Vec3& p) {
    return std::max({-(p1 - p0).cross(p - p0).dot(triN), -(p2 - p1).cross(p - p1).dot(triN),
                     -(p0 - p2).cross(p - p2).dot(triN)});
  });
  if (i3 >= 0) keep.push_back(i3);
  return keep;
}

void reducePair(const std::vector<Contact>& cs, std::size_t begin, std::size_t end,
                std::vector<Contact>& out) {
  std::vector<int> order(end - begin);
  std::iota(order.begin(), order.end(), static_cast<int>(begin));
  std::stable_sort(order.begin(), order.end(),
                   [&](int x, int y) { return cs[x].depth > cs[y].depth; });
  std::vector<std::vector<int>> patches;
  std::vector<Vec3> seeds;
  for (int i : order) {
    std::size_t k = 0;
    while (k < patches.size() && seeds[k].dot(cs[i].normal) < kSamePatchCos) ++k;
    if (k == patches.size()) {
      patches.emplace_back();
      seeds.push_back(cs[i].normal);
    }
    patches[k].push_back(i);
  }
  for (const std::vector<int>& patch : patches) {
    if (static_cast<int>(patch.size()) <= kContactsPerPatch) {
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

// Triangle / axis-aligned box overlap by the separating axis theorem. Two convex sets are
// disjoint iff some axis separates their projections; for a triangle and a box it suffices to
// try the 3 box face normals, the triangle normal, and the 9 cross products of a box edge
// direction with a triangle edge. Projections are compared with non-strict inequalities, so
// sets that merely touch (a vertex on a face, an edge on an edge) count as overlapping: a
// triangle lying in a face shared by two voxels marks both as surface voxels, which keeps the
// tree conservative.
#include "sim/shape/voxelize.h"

#include <algorithm>
#include <cmath>

namespace vf {
namespace {

// True if `axis` separates the triangle (v0, v1, v2), given relative to the box centre, from
// the box of half size h. A zero axis (parallel edges) projects everything to 0: never
// separating, which is correct because another axis covers that case.
bool separatedOn(const Vec3& axis, const Vec3& h, const Vec3& v0, const Vec3& v1, const Vec3& v2) {
  const double p0 = axis.dot(v0), p1 = axis.dot(v1), p2 = axis.dot(v2);
  const double r =
      h.x() * std::abs(axis.x()) + h.y() * std::abs(axis.y()) + h.z() * std::abs(axis.z());
  return std::min({p0, p1, p2}) > r || std::max({p0, p1, p2}) < -r;
}

}  // namespace

bool triangleBoxOverlap(const Vec3& boxCenter, const Vec3& boxHalfSize, const Vec3& a,
                        const Vec3& b, const Vec3& c) {
  const Vec3 v0 = a - boxCenter, v1 = b - boxCenter, v2 = c - boxCenter;
  const Vec3& h = boxHalfSize;

  // Box face normals: the triangle's bounding box against the box (cheapest, most decisive).
  for (int k = 0; k < 3; ++k) {
    if (std::min({v0[k], v1[k], v2[k]}) > h[k] || std::max({v0[k], v1[k], v2[k]}) < -h[k])
      return false;
  }

  const Vec3 e0 = v1 - v0, e1 = v2 - v1, e2 = v0 - v2;

  // Triangle normal: the plane n.x = n.v0 against the box's projected radius.
  const Vec3 n = e0.cross(e1);
  const double r = h.x() * std::abs(n.x()) + h.y() * std::abs(n.y()) + h.z() * std::abs(n.z());
  if (std::abs(n.dot(v0)) > r) return false;

  // The 9 edge-edge axes: unit box axis u_k x triangle edge e_j.
  for (const Vec3* e : {&e0, &e1, &e2}) {
    for (int k = 0; k < 3; ++k) {
      const Vec3 axis = Vec3::Unit(k).cross(*e);
      if (separatedOn(axis, h, v0, v1, v2)) return false;
    }
  }
  return true;
}

}  // namespace vf

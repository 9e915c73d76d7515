#include "sim/geometry/tri_mesh.h"

#include <utility>

namespace vf {

Eigen::AlignedBox3d TriMesh::bounds() const {
  Eigen::AlignedBox3d box;  // default-constructed: empty
  for (const Vec3& v : vertices) box.extend(v);
  return box;
}

void TriMesh::scale(const Vec3& factors) {
  for (Vec3& v : vertices) v = v.cwiseProduct(factors);
  // A reflection (odd number of negative factors) turns CCW triangles into CW ones: swap two
  // corners so the mesh stays outward-oriented and its volume stays positive.
  if (factors.x() * factors.y() * factors.z() < 0) {
    for (auto& t : triangles) std::swap(t[1], t[2]);
  }
}

void TriMesh::translate(const Vec3& offset) {
  for (Vec3& v : vertices) v += offset;
}

}  // namespace vf

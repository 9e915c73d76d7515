// A triangle mesh: shared vertices and counter-clockwise (outward) triangles.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "sim/core/math.h"

namespace vf {

struct TriMesh {
  std::vector<Vec3> vertices;
  std::vector<std::array<std::uint32_t, 3>>
      triangles;  // indices into vertices, CCW seen from outside

  // Axis-aligned bounds of the vertices.
  Eigen::AlignedBox3d bounds() const;
  // Applies p -> scale .* p to every vertex (a negative product of the factors flips triangles
  // back to outward orientation).
  void scale(const Vec3& factors);
  // Applies p -> p + offset to every vertex.
  void translate(const Vec3& offset);
};

}  // namespace vf

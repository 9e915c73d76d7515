// Surface voxels: the voxels of a cube grid that the mesh surface passes through (section 3).
#pragma once

#include <cstdint>
#include <vector>

#include "sim/core/math.h"
#include "sim/geometry/tri_mesh.h"

namespace vf {

// Exact triangle / axis-aligned box overlap (separating axis test over the 13 axes: 3 box
// normals, the triangle normal, 9 edge cross products). Touching counts as overlapping.
bool triangleBoxOverlap(const Vec3& boxCenter, const Vec3& boxHalfSize, const Vec3& a,
                        const Vec3& b, const Vec3& c);

}  // namespace vf

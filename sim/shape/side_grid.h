// Which side of a closed mesh's surface each cell of a coarse grid over its bounds lies on:
// outside, inside, or unknown because the surface passes near the cell. Diagnostics only: a
// point in an outside cell is outside the solid, so the true-mesh check skips the nearest-point
// search it would otherwise make for that point only to learn "outside" (most of the samples
// of a block resting in the barrel's cavity, say). It never changes what the diagnostics find.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "sim/core/math.h"
#include "sim/geometry/cell_grid.h"
#include "sim/geometry/mesh_bvh.h"
#include "sim/geometry/tri_mesh.h"

namespace vf {

class SideGrid {
 public:
  enum class Side : std::uint8_t { kOutside, kInside, kNearSurface };

  // A grid of about `cellsAlongLongest` cubes along the bounds' longest side over a closed,
  // outward, manifold mesh (validateClosedMesh's contract); `bvh` is that mesh's hierarchy.
  SideGrid(const TriMesh& mesh, const MeshBvh& bvh, int cellsAlongLongest = kDefaultCells);

  // The side of point p (mesh frame). Outside the mesh's bounds: kOutside.
  Side side(const Vec3& p) const;

  // The mesh's bounds, which the grid covers.
  Eigen::AlignedBox3d bounds() const { return {grid_.lo, hi_}; }
  // Grid cells per axis and bytes held.
  const std::array<int, 3>& cells() const { return grid_.n; }
  std::size_t memoryBytes() const { return side_.capacity() * sizeof(Side); }

  static constexpr int kDefaultCells = 32;

 private:
  CellGrid grid_;           // over the mesh's bounds, from their lower corner...
  Vec3 hi_ = Vec3::Zero();  // ...to their upper one
  std::vector<Side> side_;  // per cell, in CellGrid::index order
};

}  // namespace vf

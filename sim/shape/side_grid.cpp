// A cell the surface does not pass through lies wholly on one side of it (the cell is convex,
// and a path from inside to outside crosses the surface), and so does a face-connected group
// of such cells. So: mark every cell a triangle touches (exact triangle-box test, the cell
// widened by a margin), flood the unmarked cells into face-connected groups, and classify each
// group once, by the exact inside test at the centre of its first cell, which lies at least
// half a cell from the surface.
//
// The margin (1 % of a cell) keeps two things away from the surface by more than round-off:
// a point whose cell index rounds into a neighbouring cell, and the points where side() says
// outside or inside, for which the hierarchy's own test would otherwise decide (its answer is
// exact away from the surface, mesh_bvh.h). So side() never contradicts MeshBvh::nearest.
#include "sim/shape/side_grid.h"

#include <algorithm>
#include <cmath>

#include "sim/core/error.h"
#include "sim/shape/voxelize.h"

namespace vf {

SideGrid::SideGrid(const TriMesh& mesh, const MeshBvh& bvh, int cellsAlongLongest) {
  VF_ASSERT(cellsAlongLongest >= 1);
  const Eigen::AlignedBox3d box = mesh.bounds();
  VF_ASSERT(box.sizes().minCoeff() > 0);  // a closed, non-flat mesh
  grid_ = CellGrid(box, cellsAlongLongest);
  hi_ = box.max();
  const CellGrid& g = grid_;
  side_.assign(g.count(), Side::kOutside);

  // Cells the surface touches, each widened by the margin.
  const double margin = 0.01 * g.cell;
  const Vec3 half = Vec3::Constant(0.5 * g.cell + margin);
  std::vector<char> near(g.count(), 0);
  for (const auto& t : mesh.triangles) {
    const Vec3 &a = mesh.vertices[t[0]], &b = mesh.vertices[t[1]], &c = mesh.vertices[t[2]];
    const Vec3 tlo = a.cwiseMin(b).cwiseMin(c).array() - margin;
    const Vec3 thi = a.cwiseMax(b).cwiseMax(c).array() + margin;
    for (int k = g.along(2, tlo.z()); k <= g.along(2, thi.z()); ++k)
      for (int j = g.along(1, tlo.y()); j <= g.along(1, thi.y()); ++j)
        for (int i = g.along(0, tlo.x()); i <= g.along(0, thi.x()); ++i) {
          const std::size_t at = g.index(i, j, k);
          if (!near[at] && triangleBoxOverlap(g.centre(i, j, k), half, a, b, c)) near[at] = 1;
        }
  }

  // Face-connected groups of the other cells, each classified at its first cell's centre.
  std::vector<char> done(near);
  std::vector<std::array<int, 3>> stack;
  for (int k = 0; k < g.n[2]; ++k)
    for (int j = 0; j < g.n[1]; ++j)
      for (int i = 0; i < g.n[0]; ++i) {
        if (done[g.index(i, j, k)]) continue;
        const Side s = bvh.nearest(g.centre(i, j, k)).inside ? Side::kInside : Side::kOutside;
        stack.push_back({i, j, k});
        done[g.index(i, j, k)] = 1;
        while (!stack.empty()) {
          const std::array<int, 3> c = stack.back();
          stack.pop_back();
          side_[g.index(c[0], c[1], c[2])] = s;
          for (int axis = 0; axis < 3; ++axis)
            for (int step : {-1, 1}) {
              std::array<int, 3> m = c;
              m[axis] += step;
              if (m[axis] < 0 || m[axis] >= g.n[axis]) continue;
              const std::size_t at = g.index(m[0], m[1], m[2]);
              if (done[at]) continue;
              done[at] = 1;
              stack.push_back(m);
            }
        }
      }
  for (std::size_t c = 0; c < g.count(); ++c)
    if (near[c]) side_[c] = Side::kNearSurface;
}

SideGrid::Side SideGrid::side(const Vec3& p) const {
  // Outside the bounds (NaN too): outside the closed mesh, which they enclose.
  const Vec3& lo = grid_.lo;
  if (!(p.x() >= lo.x() && p.y() >= lo.y() && p.z() >= lo.z() && p.x() <= hi_.x() &&
        p.y() <= hi_.y() && p.z() <= hi_.z()))
    return Side::kOutside;
  return side_[grid_.cellOf(p)];
}

}  // namespace vf

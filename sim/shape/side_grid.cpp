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
  lo_ = box.min();
  hi_ = box.max();
  const Vec3 size = hi_ - lo_;
  VF_ASSERT(size.minCoeff() > 0);  // a closed, non-flat mesh
  cell_ = size.maxCoeff() / cellsAlongLongest;
  for (int k = 0; k < 3; ++k) n_[k] = std::max(1, static_cast<int>(std::ceil(size[k] / cell_)));
  const std::size_t count = static_cast<std::size_t>(n_[0]) * n_[1] * n_[2];
  side_.assign(count, Side::kOutside);
  const std::size_t nx = static_cast<std::size_t>(n_[0]), ny = static_cast<std::size_t>(n_[1]);
  auto index = [&](int i, int j, int k) {
    return static_cast<std::size_t>(i) + nx * (static_cast<std::size_t>(j) + ny * k);
  };
  auto cellOf = [&](double x, int axis) {
    return std::clamp(static_cast<int>(std::floor((x - lo_[axis]) / cell_)), 0, n_[axis] - 1);
  };

  // Cells the surface touches, each widened by the margin.
  const double margin = 0.01 * cell_;
  const Vec3 half = Vec3::Constant(0.5 * cell_ + margin);
  std::vector<char> near(count, 0);
  for (const auto& t : mesh.triangles) {
    const Vec3 &a = mesh.vertices[t[0]], &b = mesh.vertices[t[1]], &c = mesh.vertices[t[2]];
    const Vec3 tlo = a.cwiseMin(b).cwiseMin(c).array() - margin;
    const Vec3 thi = a.cwiseMax(b).cwiseMax(c).array() + margin;
    for (int k = cellOf(tlo.z(), 2); k <= cellOf(thi.z(), 2); ++k)
      for (int j = cellOf(tlo.y(), 1); j <= cellOf(thi.y(), 1); ++j)
        for (int i = cellOf(tlo.x(), 0); i <= cellOf(thi.x(), 0); ++i) {
          const std::size_t c0 = index(i, j, k);
          if (near[c0]) continue;
          const Vec3 centre = lo_ + cell_ * Vec3(i + 0.5, j + 0.5, k + 0.5);
          if (triangleBoxOverlap(centre, half, a, b, c)) near[c0] = 1;
        }
  }

  // Face-connected groups of the other cells, each classified at its first cell's centre.
  std::vector<char> done(near);
  std::vector<std::array<int, 3>> stack;
  for (int k = 0; k < n_[2]; ++k)
    for (int j = 0; j < n_[1]; ++j)
      for (int i = 0; i < n_[0]; ++i) {
        if (done[index(i, j, k)]) continue;
        const Vec3 centre = lo_ + cell_ * Vec3(i + 0.5, j + 0.5, k + 0.5);
        const Side s = bvh.nearest(centre).inside ? Side::kInside : Side::kOutside;
        stack.push_back({i, j, k});
        done[index(i, j, k)] = 1;
        while (!stack.empty()) {
          const std::array<int, 3> c = stack.back();
          stack.pop_back();
          side_[index(c[0], c[1], c[2])] = s;
          for (int axis = 0; axis < 3; ++axis)
            for (int step : {-1, 1}) {
              std::array<int, 3> m = c;
              m[axis] += step;
              if (m[axis] < 0 || m[axis] >= n_[axis]) continue;
              const std::size_t mi = index(m[0], m[1], m[2]);
              if (done[mi]) continue;
              done[mi] = 1;
              stack.push_back(m);
            }
        }
      }
  for (std::size_t c = 0; c < count; ++c)
    if (near[c]) side_[c] = Side::kNearSurface;
}

SideGrid::Side SideGrid::side(const Vec3& p) const {
  // Outside the bounds (NaN too): outside the closed mesh, which they enclose.
  if (!(p.x() >= lo_.x() && p.y() >= lo_.y() && p.z() >= lo_.z() && p.x() <= hi_.x() &&
        p.y() <= hi_.y() && p.z() <= hi_.z()))
    return Side::kOutside;
  std::size_t at = 0, stride = 1;
  for (int axis = 0; axis < 3; ++axis) {
    const int i = std::min(static_cast<int>((p[axis] - lo_[axis]) / cell_), n_[axis] - 1);
    at += stride * static_cast<std::size_t>(i);
    stride *= static_cast<std::size_t>(n_[axis]);
  }
  return side_[at];
}

}  // namespace vf

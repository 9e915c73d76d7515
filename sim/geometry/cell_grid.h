// A uniform grid of cubes over a box: so many cells along the box's longest side, as many as
// cover each other side (at least one). Cell (i, j, k) spans lo + cell * [i, i + 1] etc.; a
// point is in the cell its coordinates floor to, clamped to the grid. Used by the diagnostics'
// side grid (sim/shape/side_grid.h) and sample clusters (mesh_query.h).
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>

#include "sim/core/math.h"

namespace vf {

// The index of the cell that coordinate q (in cells from the first cell's start) lies in:
// floor(q) clamped to [0, last]. Clamped first, a value >= 0 truncates to its floor, so this is a
// conversion rather than a rounding call, and a far-off q never overflows an int. q not NaN.
inline int cellIndex(double q, int last) {
  return static_cast<int>(std::clamp(q, 0.0, static_cast<double>(last)));
}

struct CellGrid {
  Vec3 lo = Vec3::Zero();
  double cell = 1;  // side of a cell
  std::array<int, 3> n{1, 1, 1};

  CellGrid() = default;
  CellGrid(const Eigen::AlignedBox3d& box, int cellsAlongLongest)
      : lo(box.min()),
        cell(std::max(box.sizes().maxCoeff(), 1e-300) / std::max(cellsAlongLongest, 1)) {
    for (int k = 0; k < 3; ++k)
      n[k] = std::max(1, static_cast<int>(std::ceil(box.sizes()[k] / cell)));
  }

  std::size_t count() const {
    return static_cast<std::size_t>(n[0]) * static_cast<std::size_t>(n[1]) *
           static_cast<std::size_t>(n[2]);
  }
  // The cell index along `axis` of coordinate x.
  int along(int axis, double x) const { return cellIndex((x - lo[axis]) / cell, n[axis] - 1); }
  std::size_t index(int i, int j, int k) const {
    return static_cast<std::size_t>(i) +
           static_cast<std::size_t>(n[0]) *
               (static_cast<std::size_t>(j) + static_cast<std::size_t>(n[1]) * k);
  }
  std::size_t cellOf(const Vec3& p) const {
    return index(along(0, p.x()), along(1, p.y()), along(2, p.z()));
  }
  Vec3 centre(int i, int j, int k) const { return lo + cell * Vec3(i + 0.5, j + 0.5, k + 0.5); }
};

}  // namespace vf

// Forest edges for maps (see forest_outline.h).
#include "sim/ground/forest_outline.h"

#include "sim/ground/forest.h"
#include "sim/shape/heightfield.h"

namespace vf {

std::vector<std::array<std::array<double, 2>, 2>> forestOutline(const Forest& forest) {
  const Heightfield& g = *forest.grid;
  const auto stems = [&](int i, int j) {
    return i >= 0 && j >= 0 && i < g.nx && j < g.ny &&
           forest.density[static_cast<std::size_t>(j) * g.nx + i] > 0;
  };
  const double h = 0.5 * g.cell;
  std::vector<std::array<std::array<double, 2>, 2>> out;
  // Horizontal sides: between rows j - 1 and j, at y = y0 + (j - 1/2) cell.
  for (int j = 0; j <= g.ny; ++j) {
    const double y = g.y0 + j * g.cell - h;
    int start = -1;
    for (int i = 0; i <= g.nx; ++i) {
      const bool edge = i < g.nx && stems(i, j - 1) != stems(i, j);
      if (edge && start < 0) start = i;
      if (!edge && start >= 0) {
        out.push_back({{{g.x0 + start * g.cell - h, y}, {g.x0 + i * g.cell - h, y}}});
        start = -1;
      }
    }
  }
  // Vertical sides: between columns i - 1 and i, at x = x0 + (i - 1/2) cell.
  for (int i = 0; i <= g.nx; ++i) {
    const double x = g.x0 + i * g.cell - h;
    int start = -1;
    for (int j = 0; j <= g.ny; ++j) {
      const bool edge = j < g.ny && stems(i - 1, j) != stems(i, j);
      if (edge && start < 0) start = j;
      if (!edge && start >= 0) {
        out.push_back({{{x, g.y0 + start * g.cell - h}, {x, g.y0 + j * g.cell - h}}});
        start = -1;
      }
    }
  }
  return out;
}

}  // namespace vf

// A terrain drawn as the solid the physics treats it as (sim/collide/tree_terrain_descent.cpp: the
// ground is solid below the surface, and where the data ends its border is a vertical wall):
// the surface from the DEM, and here its sides and base, so that seen from the side or from
// below a terrain is a block of ground instead of a sheet with the floor showing through.
#pragma once

#include <optional>

#include "sim/geometry/tri_mesh.h"
#include "sim/shape/heightfield.h"

namespace vf {

// The level of the solid's base: the floor plane where one lies at or below the lowest sample
// (the terrain stands on the floor, with no gap under its walls and nothing drawn, or casting
// shadows, under the floor); otherwise below the lowest sample by the larger of one cell and
// 5 % of the relief, a visible thickness at any scale.
double terrainBase(const Heightfield& h, std::optional<double> floor);

// The sides and base: a vertical wall under every edge of a cell with data where the cell
// across that edge has none (the grid's border, NODATA holes), from the edge's two samples down
// to `base` (none where both lie at `base`); and, with `closeBase`, under every run of cells
// with data along a row a face at `base`. Without it the solid is open at the bottom, for a
// terrain standing on the floor: there the base would be hidden by the floor and would fight
// the surface for depth wherever the surface lies on the floor. Triangles face outwards; each
// wall quad has vertices of its own, so it shades flat.
TriMesh terrainSides(const Heightfield& h, double base, bool closeBase = true);

}  // namespace vf

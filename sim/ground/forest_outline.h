// The edge of a forest stand, for maps: where a sample with stems meets one without (or the
// grid's border), as straight world (x, y) segments along the sides of the samples' cells.
#pragma once

#include <array>
#include <vector>

namespace vf {

struct Forest;

// Each segment is two points, world x, y (m). A cell is the square of side `cell` centred on its
// sample; runs of sides along one row or column are joined into one segment. Order: horizontal
// segments row by row from the south, then vertical ones column by column from the west.
std::vector<std::array<std::array<double, 2>, 2>> forestOutline(const Forest& forest);

}  // namespace vf

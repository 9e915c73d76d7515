// Rock meshes generated from a class, a seed and a size, for scenes that have no scan of their
// blocks: the EOTA test blocks of rock-fall barrier testing, and natural rocks in the four
// form classes of Zingg. A generated mesh is closed, convex and wound outward, and goes through
// the same mass properties and voxelisation as a mesh file. Construction, class ratios and
// their sources: docs/rockfall.md, "Rock shapes".
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "sim/core/math.h"
#include "sim/geometry/tri_mesh.h"

namespace vf {

// What a rock is made from. Exactly one of `extents`, `length` and `volume` is set (> 0).
struct RockDef {
  std::string shapeClass;       // one of rockClassNames()
  std::uint64_t seed = 1;       // which rock of a natural class; the EOTA blocks ignore it
  Vec3 extents = Vec3::Zero();  // m, the rock's lengths along its x, y and z axes
  double length = 0;            // m, the longest extent; the others follow the class's ratios
  double volume = 0;            // m^3; the extents follow the class's ratios
};

// The classes, in the order the manual lists them: "eota_111", "eota_221", "compact", "flat",
// "elongated", "bladed".
const std::vector<std::string>& rockClassNames();
bool isRockClass(const std::string& name);

// "" when extents along x, y, z fit the class, else why not: a natural class needs extents in
// its Zingg form class (sorted a >= b >= c, b/a and c/b each on its side of 2/3); the EOTA
// blocks take any extents (the block is stretched to them).
std::string rockExtentsProblem(const std::string& shapeClass, const Vec3& extents);

// The rock's mesh, a pure function of `def` (bit-identical on every machine: integer and IEEE
// basic arithmetic and square roots only). Centred on the middle of its bounding box, whose
// edges along x, y and z are the rock's extents. The class must be one of rockClassNames().
TriMesh makeRockMesh(const RockDef& def);

// The cube root of x > 0 by Newton's iteration from a fixed start: the same bits everywhere,
// which std::cbrt does not promise across C libraries. Within 1 ulp of the true root (0.95 ulp
// at worst over 10^7 random arguments).
double portableCubeRoot(double x);

}  // namespace vf

// Checks that a mesh can be a rigid body: closed, no degenerate triangles, non-zero volume.
#pragma once

#include <string>

#include "sim/geometry/tri_mesh.h"

namespace vf {

// Throws InputError with `where` (usually the file path) and what is wrong, with a count and
// one example (e.g. "mesh is not closed: 42 boundary edges, e.g. between vertices 3 and 17").
// Checks, in order: at least 4 triangles; no degenerate (zero-area) triangle; every edge shared
// by exactly two triangles with opposite orientation (closed, consistently oriented, manifold);
// non-zero enclosed volume. If the volume is negative (inward triangles) the mesh is flipped
// in place rather than rejected.
void validateClosedMesh(TriMesh& mesh, const std::string& where);

}  // namespace vf

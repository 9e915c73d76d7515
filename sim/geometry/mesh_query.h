// Geometric queries on a closed mesh, used by diagnostics (true-mesh interpenetration and
// tunnelling), never inside the collision pipeline.
#pragma once

#include <vector>

#include "sim/core/math.h"
#include "sim/geometry/tri_mesh.h"

namespace vf {

// True if p is strictly inside the closed mesh (generalised winding number > 1/2).
bool pointInsideMesh(const TriMesh& mesh, const Vec3& p);

// Unsigned distance from p to the nearest point of the mesh surface.
double distanceToMesh(const TriMesh& mesh, const Vec3& p);

// Points on the surface for penetration sampling: every vertex, every edge midpoint and every
// triangle centroid.
std::vector<Vec3> surfaceSamples(const TriMesh& mesh);

}  // namespace vf

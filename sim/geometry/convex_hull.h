// The convex hull of a point set as a closed, outward-wound triangle mesh (CGAL's convex_hull_3
// in convex_hull.cpp, which is built with mesh_repair.cpp as the small CGAL library).
#pragma once

#include <vector>

#include "sim/core/math.h"
#include "sim/geometry/tri_mesh.h"

namespace vf {

// The hull's vertices are copies of input points, bit for bit (none is constructed), in input
// order; points inside the hull or repeated are left out. Its triangles wind counter-clockwise
// seen from outside, each listed from its smallest vertex index, in sorted order; a planar face
// of more than three points is a fan from its smallest vertex index. So the mesh is a function
// of the points alone.
// Needs at least four points not on one plane (VF_ASSERT): callers generate their points.
TriMesh convexHull(const std::vector<Vec3>& points);

}  // namespace vf

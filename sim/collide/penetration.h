// Interpenetration of the TRUE meshes (not the spheres): the measure that shows whether the
// eq.-20 step keeps bodies apart. Diagnostics only; never used to resolve contacts.
#pragma once

#include "sim/core/math.h"
#include "sim/shape/heightfield.h"
#include "sim/shape/shape.h"

namespace vf {

struct Pose {
  Vec3 x = Vec3::Zero();
  Quat q = Quat::Identity();
};

// Deepest surface sample of A (vertices, edge midpoints, triangle centroids) inside B,
// measured as its distance to B's surface, in m; 0 if no sample of A is inside B.
double meshPenetration(const Shape& a, const Pose& pa, const Shape& b, const Pose& pb);

// How far the lowest vertex lies below the plane z = height, in m; 0 if none does.
double groundPenetration(const Shape& s, const Pose& p, double height);

// How far the lowest vertex lies below the terrain surface, in m; 0 if none does. Vertices
// outside the grid or over missing data are not counted.
double terrainPenetration(const Shape& s, const Pose& p, const Heightfield& terrain);

// True if the world point lies inside the body's mesh.
bool pointInsideBody(const Shape& s, const Pose& p, const Vec3& point);

}  // namespace vf

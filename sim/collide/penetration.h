// Interpenetration of the TRUE meshes (not the spheres): the measure that shows whether the
// eq.-20 step keeps bodies apart. Diagnostics only; never used to resolve contacts.
#pragma once

#include <optional>
#include <vector>

#include "sim/core/body.h"
#include "sim/core/math.h"
#include "sim/shape/heightfield.h"
#include "sim/shape/shape.h"

namespace vf {

struct Pose {
  Vec3 x = Vec3::Zero();
  Quat q = Quat::Identity();
};

// Deepest surface sample of A (vertices, edge midpoints, triangle centroids) inside B,
// measured as its distance to B's surface, in m; 0 if no sample of A is inside B. With
// `atLeast`: the larger of that and atLeast, found faster (a sample that cannot be deeper than
// the deepest so far is dropped as soon as a surface point that near is found).
double meshPenetration(const Shape& a, const Pose& pa, const Shape& b, const Pose& pb,
                       double atLeast = 0);

// How far the lowest vertex lies below the plane z = height, in m; 0 if none does.
double groundPenetration(const Shape& s, const Pose& p, double height);

// How far the lowest vertex lies below the terrain surface, in m; 0 if none does. Vertices
// outside the grid or over missing data are not counted.
double terrainPenetration(const Shape& s, const Pose& p, const Heightfield& terrain);

// True if the world point lies inside the body's mesh.
bool pointInsideBody(const Shape& s, const Pose& p, const Vec3& point);

// Checks of the TRUE meshes (not the spheres) at one instant; see World::measure().
struct Diagnostics {
  double maxPenetrationBodyBody = 0;    // m, deepest point of one mesh inside another
  double maxPenetrationBodyGround = 0;  // m, deepest vertex below the floor or the terrain
  int tunnelled = 0;  // bodies whose centre of mass is inside another body or below the ground
  double kineticEnergy = 0;    // J, dynamic bodies
  double potentialEnergy = 0;  // J, -m g.x relative to the origin
};

// World::measure(): the diagnostics of every active body in the given state, pairs culled by
// their bounding spheres (SAP, as the broad phase) and every surface sample tested exactly
// against the other mesh through its triangle hierarchy (mesh_bvh.h).
Diagnostics measureDiagnostics(const std::vector<BodyInfo>& bodies,
                               const std::vector<BodyState>& states, const Vec3& gravity,
                               const std::optional<double>& groundHeight,
                               const Heightfield* terrain);

}  // namespace vf

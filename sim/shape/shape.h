// A shape: a mesh in its body frame, its mass properties and its voxel sphere tree.
// Built once, immutable, shared by every body that uses it (shared_ptr<const Shape>).
#pragma once

#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "sim/core/math.h"
#include "sim/geometry/mass_properties.h"
#include "sim/geometry/mesh_bvh.h"
#include "sim/geometry/mesh_query.h"
#include "sim/geometry/tri_mesh.h"
#include "sim/shape/side_grid.h"
#include "sim/shape/sphere_tree.h"

namespace vf {

struct ConvexPolyhedron;

struct Shape {
  std::string name;
  TriMesh mesh;       // body frame: centre of mass at the origin, mesh-file axes
  Vec3 meshOrigin;    // where the mesh file's origin lies in the body frame (= -com)
  double mass = 0;    // kg
  double volume = 0;  // m^3
  Mat3 inertiaBody;   // kg m^2 about the centre of mass
  Mat3 inertiaBodyInv;
  double diameter = 0;       // l of eq. 18-20: twice the largest vertex distance from the origin
  bool centerInside = true;  // the centre of mass lies inside the solid (false for a hollow
                             // body such as the barrel): only then can it witness tunnelling
  std::shared_ptr<const SphereTree> tree;  // shared between shapes with the same mesh+scale+level
  // Set when the scene selects the polygon collider (collider = "polygon"): the body then
  // collides by its convex polyhedron; the tree still serves eq. 20 and release checks.
  std::shared_ptr<const ConvexPolyhedron> polyhedron;
  // Diagnostics only (collide/penetration.cpp): the triangle hierarchy for exact point queries,
  // the grid that answers them at once away from the surface, and the surface samples
  // (vertices, edge midpoints, centroids) whose depth is measured, in clusters.
  std::shared_ptr<const MeshBvh> bvh;
  std::shared_ptr<const SideGrid> sides;
  SampleClusters surfaceSamples;

  // r of eq. 19, l / 2^(Lv + 1): how far the step rules (eq. 17) let a point of the body move
  // in a step.
  double stepRadius() const { return std::ldexp(diameter, -(tree->leafLevel() + 1)); }
};

// Builds a shape from a validated mesh in file coordinates: scales it, computes mass
// properties with `density`, moves the centre of mass to the origin. `tree` must have been
// built from the same scaled, centred mesh (see centredMesh) or be null to build it here.
std::shared_ptr<const Shape> makeShape(std::string name, TriMesh meshFileCoords, const Vec3& scale,
                                       double density, int level,
                                       std::shared_ptr<const SphereTree> tree = nullptr);

// The mesh scaled by `scale` and moved so its centre of mass is at the origin; the key from
// which a sphere tree is built (independent of density).
TriMesh centredMesh(TriMesh meshFileCoords, const Vec3& scale);

}  // namespace vf

#include "sim/shape/shape.h"

#include <algorithm>
#include <utility>

#include "sim/core/error.h"
#include "sim/geometry/mesh_query.h"

namespace vf {
namespace {

// Scales the mesh in place and moves its centre of mass to the origin. Returns the mass
// properties of the scaled mesh before the move (centre of mass in scaled file coordinates).
// makeShape and centredMesh share this so that a tree built from centredMesh() is built from
// a mesh bit-identical to Shape::mesh (the centre of mass does not depend on density).
MassProperties scaleAndCentre(TriMesh& mesh, const Vec3& scale, double density) {
  mesh.scale(scale);
  const MassProperties mp = computeMassProperties(mesh, density);
  mesh.translate(-mp.centerOfMass);
  return mp;
}

}  // namespace

TriMesh centredMesh(TriMesh meshFileCoords, const Vec3& scale) {
  scaleAndCentre(meshFileCoords, scale, 1.0);
  return meshFileCoords;
}

std::shared_ptr<const Shape> makeShape(std::string name, TriMesh meshFileCoords, const Vec3& scale,
                                       double density, int level,
                                       std::shared_ptr<const SphereTree> tree) {
  VF_ASSERT(density > 0);
  VF_ASSERT(level >= kMinLevel && level <= kMaxLevel);
  auto shape = std::make_shared<Shape>();
  shape->name = std::move(name);
  shape->mesh = std::move(meshFileCoords);
  const MassProperties mp = scaleAndCentre(shape->mesh, scale, density);
  VF_ASSERT(mp.volume > 0);  // validateClosedMesh first: outward, closed, non-flat

  shape->meshOrigin = -mp.centerOfMass;
  shape->mass = mp.mass;
  shape->volume = mp.volume;
  shape->inertiaBody = mp.inertia;  // about the centre of mass; translation does not change it
  shape->inertiaBodyInv = mp.inertia.inverse();
  double farthest = 0;
  for (const Vec3& v : shape->mesh.vertices) farthest = std::max(farthest, v.norm());
  shape->diameter = 2 * farthest;  // l of eqs. 18-20
  shape->centerInside = pointInsideMesh(shape->mesh, Vec3::Zero());
  shape->bvh = std::make_shared<const MeshBvh>(shape->mesh);
  shape->sides = std::make_shared<const SideGrid>(shape->mesh, *shape->bvh);
  shape->surfaceSamples = clusterSamples(surfaceSamples(shape->mesh));

  if (tree == nullptr)
    tree = std::make_shared<const SphereTree>(buildSphereTree(shape->mesh, level));
  VF_ASSERT(tree->leafLevel() == level);
  shape->tree = std::move(tree);
  return shape;
}

}  // namespace vf

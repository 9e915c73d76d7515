// Helpers that keep the physics tests short (Jolt's PhysicsTestContext habit): closed box
// meshes, shapes at a chosen level, and worlds built from them.
#pragma once

#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "sim/geometry/tri_mesh.h"
#include "sim/ground/rock_fall_world.h"
#include "sim/shape/heightfield.h"
#include "sim/shape/shape.h"
#include "sim/world.h"

namespace vf::test {

// Closed, outward box mesh of size a x b x c centred at the origin (8 vertices, 12 triangles).
TriMesh boxMesh(double a, double b, double c);

// A box shape of the given size and density at voxel level `level`.
std::shared_ptr<const Shape> boxShape(double a, double b, double c, double density, int level);
// A body of shape `s` with its centre of mass at x (m), released at `release` (s).
BodyDef bodyAt(std::shared_ptr<const Shape> s, const Vec3& x, double release = 0);

// One dynamic body of shape s, for the narrow phase's own tests (findContacts).
std::vector<BodyInfo> oneBody(std::shared_ptr<const Shape> s);

// Lowest point of the body's leaf spheres below its centre of mass when unrotated: place a
// body at z = ground + restOffset(...) for its spheres to just touch the floor.
double restOffset(const Shape& s);

// A body dropped onto the floor: what its first bounce did. Steps `world` by `dt` until
// `until` seconds; body 0's vertical velocity before and after the step in which it turned
// from falling to rising, and the highest centre height after that, minus `zTouch`.
struct Rebound {
  bool bounced = false;
  double vBefore = 0, vAfter = 0;  // m/s
  double apex = 0;                 // m above zTouch
};
Rebound dropAndWatchRebound(World& world, double zTouch, double dt, double until);

// A world with rock fall attached (sim/ground/rock_fall_world.h) before any body, as a scene
// builds one.
struct RockFallWorld {
  RockFallWorld(WorldDef def, RockFallDef rockFallDef)
      : world(std::move(def)), rockFall(attachRockFall(world, std::move(rockFallDef))) {}
  bool allSettled() const { return rockFall.allSettled(world.bodies()); }
  World world;
  RockFall& rockFall;
};

// Rock fall with ground map `ground` and every other setting at its default.
inline RockFallDef groundLaws(std::shared_ptr<const GroundMap> ground) {
  RockFallDef def;
  def.ground = std::move(ground);
  return def;
}

// A level heightfield: nx x ny samples `cell` m apart from (x0, y0), all at height z (m).
Heightfield flatHeightfield(int nx, int ny, double cell, double z, double x0 = 0, double y0 = 0);

// Path of a file in the source tree.
std::string sourcePath(const std::string& relative);

}  // namespace vf::test

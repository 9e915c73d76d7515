// Narrow phase: leaf-sphere contacts between two colliders, dispatched by a
// [type][type] table (see narrow_phase.cpp).
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "sim/collide/contact.h"
#include "sim/core/body.h"
#include "sim/core/math.h"
#include "sim/shape/heightfield.h"
#include "sim/shape/sphere_tree.h"

namespace vf {

enum class ColliderType : int {
  kSphereTree = 0,
  kPlane = 1,
  kHeightfield = 2,
  kPolygon = 3,  // a convex polyhedron: the paper's comparison method (polygon_contact.h)
  kCount = 4
};

struct ConvexPolyhedron;

// What the narrow phase needs of one side of a pair, posed in the world.
struct Collider {
  ColliderType type = ColliderType::kSphereTree;
  int body = kGround;
  // kSphereTree: the tree and its pose (body frame -> world: p = x + R p_body).
  const SphereTree* tree = nullptr;
  Vec3 x = Vec3::Zero();
  Mat3 R = Mat3::Identity();
  // kPlane: points p with normal . p = offset; the solid is on the side -normal.
  Vec3 normal = Vec3::UnitZ();
  double offset = 0;
  // kHeightfield: terrain in world coordinates; the solid is below the surface.
  const Heightfield* terrain = nullptr;
  // kPolygon: the convex polyhedron, posed by x and R as the tree is.
  const ConvexPolyhedron* polyhedron = nullptr;
};

Collider sphereTreeCollider(int body, const SphereTree& tree, const Vec3& x, const Quat& q);
Collider planeCollider(double height);
Collider polygonCollider(int body, const ConvexPolyhedron& polyhedron, const Vec3& x,
                         const Quat& q);
Collider heightfieldCollider(const Heightfield& terrain);

// Appends the contacts between a and b (a's leaf spheres are the paper's body 1) in a fixed
// order, and returns the number of sphere tests made (feature tests for kPolygon). The
// bounding-sphere test (fig. 3 step 1) is part of it.
std::uint64_t collide(const Collider& a, const Collider& b, std::vector<Contact>& out);

// The narrow-phase stage of a step: contacts of every broad-phase pair, in pair order, then
// of every moving body with the floor plane and the terrain (if any), by body id. A body whose
// shape has a polyhedron collides by the polygon method, else by its sphere tree. Pairs of
// which neither body moves (static or asleep) are skipped. Up to `threads` threads share the
// work; the contacts and their order do not depend on it. Returns the sphere tests.
std::uint64_t findContacts(const std::vector<BodyInfo>& bodies,
                           const std::vector<BodyState>& states, const std::vector<BodyPair>& pairs,
                           const std::optional<double>& groundHeight, const Heightfield* terrain,
                           int threads, std::vector<Contact>& out);

// Closest point of the triangle (a, b, c) to p.
Vec3 closestPointOnTriangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c);

}  // namespace vf

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
// which neither body moves (static or asleep) are skipped. The threads of `pool` (none: the
// calling thread alone) share the work; the contacts and their order do not depend on it.
// With `reduce` each collider pair's contacts are replaced by their representatives
// (contact_reduction.h) by the thread that found them. Returns the sphere tests and the leaf
// contacts found (before any reduction).
//
// `candidates`, when given, carries leaf-pair candidates of sphere-tree pairs (body-body,
// body-plane and body-terrain) from step to step (temporal coherence): the contacts are the
// same, found for less. It expects `pairs` sorted by (a, b), as findPairs gives them (pairs
// out of that order would still get exact contacts, but would lose their candidates).
struct CandidateCache;
class WorkerPool;
struct ContactCounts {
  std::uint64_t sphereTests = 0, leafContacts = 0;
};
ContactCounts findContacts(const std::vector<BodyInfo>& bodies,
                           const std::vector<BodyState>& states, const std::vector<BodyPair>& pairs,
                           const std::optional<double>& groundHeight, const Heightfield* terrain,
                           WorkerPool* pool, std::vector<Contact>& out,
                           CandidateCache* candidates = nullptr, bool reduce = false);

// Temporal coherence of the sphere-tree descents. When a pair moved little relative to itself
// in the last step, the descent is run once with every test widened by a margin m and keeps
// the leaf pairs (or, against the plane and the terrain, the leaves) closer than touching plus
// m: its candidates, in the descent's order. While the pair's relative pose stays so close to
// the one they were found at that no leaf point has moved by m relative to the other side
// (bounded from the change of the relative rotation and translation), every touching leaf pair
// is among them, so the next steps test only the candidates, exactly as the descent tests
// leaves and in its order: the same contacts, bit for bit, for the cost of one leaf test per
// candidate (against the terrain, why: collideTreeHeightfield in tree_terrain_descent.cpp).
// Depends on the states only (never on timing or threads), like everything in a step.
struct PairCandidates {
  bool served = false;  // the current call tested only the candidates
  bool holds = false;   // candidates valid for poses near the build pose
  bool hasLast = false;
  // The pose the candidates were built at and the last test's: the relative rotation (b in a's
  // frame; plane: unused; terrain: the body's rotation), the relative translation (plane: R^T n;
  // terrain: the position) and the height of the body origin (plane). Read only where `holds`
  // or `hasLast` says they were set; initialised all the same, so that copying a fresh entry
  // copies defined values (GCC warned of them).
  Mat3 buildR = Mat3::Identity(), lastR = Mat3::Identity();
  Vec3 buildT = Vec3::Zero(), lastT = Vec3::Zero();
  double buildH = 0, lastH = 0;
  double margin = 0;
  std::vector<std::uint32_t> leaves;  // candidate leaf pairs (a, b) in pairs, or leaves of a
                                      // (plane, terrain)
  // Body pairs: where each run of candidates sharing a's leaf begins, then their number; and
  // b's leaf centres of the candidates in float (structure of arrays), for the serving test.
  std::vector<std::uint32_t> runs;
  std::vector<float> centersB;
  // Against the plane: the body-frame bounds of the centres of each group of kPatchGroup
  // consecutive candidates (contact_reduction.h), for the reduction from candidates.
  std::vector<Vec3> groupLo, groupHi;

  // Back to a fresh entry's state (every field as initialised above, no candidates), keeping
  // the lists' memory.
  void restart() {
    served = holds = hasLast = false;
    buildR = lastR = Mat3::Identity();
    buildT = lastT = Vec3::Zero();
    buildH = lastH = margin = 0;
    leaves.clear();
    runs.clear();
    centersB.clear();
    groupLo.clear();
    groupHi.clear();
  }
};
// The candidates of every sphere-tree pair that findContacts tested in its last call (a pair
// it did not test, because it is gone or nothing in it moves, starts afresh when tested again).
struct CandidateCache {
  // Body pairs: (key, slot) sorted by key (body a in the high half, body b in the low); each
  // call merges them with its own sorted pairs, so no pair is looked up by hashing. The
  // candidates themselves stay in their slot for as long as the pair is tested (a merge moves
  // 12-byte entries, not 400-byte candidates); slots of pairs gone are reused, fresh.
  std::vector<std::pair<std::uint64_t, std::uint32_t>> pairs;
  std::vector<PairCandidates> slots;
  std::vector<std::uint32_t> freeSlots;
  std::vector<PairCandidates> plane, terrain;  // each body's against the floor, the terrain
  std::uint64_t descents = 0, served = 0;      // pair tests by descent; by candidates only
};

// Closest point of the triangle (a, b, c) to p.
Vec3 closestPointOnTriangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c);

}  // namespace vf

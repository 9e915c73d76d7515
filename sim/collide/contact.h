// Contacts between leaf spheres, as the narrow phase finds them and the solver consumes them.
#pragma once

#include <compare>
#include <cstdint>
#include <vector>

#include "sim/core/math.h"

namespace vf {

constexpr int kGround = -1;  // body id of the floor plane and of the terrain
// Contact::leafB of a contact with the terrain (with the plane: 0). Both grounds are body
// kGround, and a scene may have both where they coincide (scenes/cliff.toml's valley floor lies
// on its plane): the leaf tells the two contacts of one leaf apart (ContactKey, warm starting).
constexpr std::uint32_t kTerrainLeaf = 1;

// One colliding leaf-sphere pair (section 4, fig. 5). Body `a` is the paper's body 1.
struct Contact {
  int a = 0;
  int b = kGround;              // another body, or kGround
  Vec3 point = Vec3::Zero();    // p = (x1 + x2) / 2 for two spheres; on the plane for the floor
  Vec3 normal = Vec3::UnitZ();  // n21 = (x1 - x2) / |x1 - x2|: direction of the force on `a`
  double depth = 0;             // r1 + r2 - |x1 - x2| (sphere overlap), m
  std::uint32_t leafA = 0;      // leaf-sphere index in a's tree (feature key)
  std::uint32_t leafB = 0;      // leaf-sphere index in b's tree; plane 0, terrain kTerrainLeaf
};

// How much the tests that only prune (bounding spheres in the broad phase, inner nodes of the
// sphere-tree descents) are widened, in m, for a body at x with a sphere of the given radius
// about it: a pair's slack is the sum of its two bodies'. The pruning tests round differently
// from the leaf tests (other centres, other frames), and a leaf that touches exactly where its
// ancestors' spheres touch (a box's corner leaf) would otherwise be lost to rounding of the
// coordinates; far above that rounding (1e-16 of |x|), far below any leaf radius, so it only
// lets a few more pairs through to the exact leaf tests.
inline double roundingSlack(const Vec3& x, double radius) {
  return 1e-9 * (1 + x.lpNorm<Eigen::Infinity>() + radius);
}

// A body pair whose bounding spheres overlap; a < b.
struct BodyPair {
  int a = 0;
  int b = 0;
};

// Identifies a contact across steps: the body pair and the two leaf spheres.
struct ContactKey {
  int a = 0, b = 0;
  std::uint32_t leafA = 0, leafB = 0;
  auto operator<=>(const ContactKey&) const = default;
};

}  // namespace vf

// Contact reduction: a few representative contacts per body pair instead of every colliding
// leaf-sphere pair (an extension; the paper is silent on combining leaf contacts, digest
// section 4). Selected by WorldDef::contactReduction / [simulation] contact_reduction.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <vector>

#include "sim/collide/contact.h"

namespace vf {

// Most contacts kept per patch: the deepest plus three that span the patch (Bullet keeps 4).
constexpr int kContactsPerPatch = 4;

// Replaces contacts[begin, end) -- the contacts of one collider pair, as the narrow phase
// emits them -- by their representatives, in place; see contact_reduction.cpp. A patch of at
// most kContactsPerPatch contacts is kept unchanged, so a single contact is still solved by
// eq. 15 exactly. The order stays deterministic.
void reducePairContacts(std::vector<Contact>& contacts, std::size_t begin);

// The same for every run of consecutive contacts with the same a and b, each as one pair.
void reduceContacts(std::vector<Contact>& contacts);

// The order a patch of at most kContactsPerPatch contacts is kept in: deepest first, equal
// depths in narrow-phase order (a stable sort). Writes the indices 0..m-1 so ordered to order.
void deepestFirst(const double* depths, std::size_t m, std::size_t order[kContactsPerPatch]);

// The choice of a large patch's representatives, shared by the reductions above and the narrow
// phase's reduction of a body's plane contacts from its candidates (served_plane_patch.cpp).
// Coordinates in the patch plane are taken in the basis patchPlaneBasis gives for the normal.
void patchPlaneBasis(const Vec3& n, Vec3& t1, Vec3& t2);
// A box in the patch plane bounding the coordinates of a group of points (groups of kPatchGroup
// consecutive points where the reduction makes them; groups of candidates in the narrow phase).
constexpr std::size_t kPatchGroup = 16;
struct PatchBox {
  double x0 = INFINITY, x1 = -INFINITY, y0 = INFINITY, y1 = -INFINITY;
  void extend(const Eigen::Vector2d& p) {
    x0 = std::min(x0, p.x()), x1 = std::max(x1, p.x());
    y0 = std::min(y0, p.y()), y1 = std::max(y1, p.y());
  }
};
// Chooses the representatives of a patch of m > kContactsPerPatch points (in narrow-phase
// order) whose deepest point is `deepest` (the first of the deepest): that point; the one
// farthest from it; the one that makes the largest triangle with these two; the one farthest
// outside that triangle (each the first of equals, none if no point scores above zero). Writes
// their indices, in that order, to keep and returns how many. flat[k] is point k's plane
// coordinates; the points come in `groups` groups of consecutive points, group g holding
// [groupBegin[g], groupBegin[g + 1]) and boxes[g] their coordinates. A group whose box cannot
// beat the best point so far is skipped, which gives the full scan's choice bit for bit. With
// `fill`, flat is filled lazily: flat[deepest] must be set; fill(g) must write group g's
// coordinates (it may be called more than once for a group) and is called before they are read.
int chooseRepresentatives(std::size_t m, std::size_t deepest, const Eigen::Vector2d* flat,
                          const PatchBox* boxes, const std::size_t* groupBegin, std::size_t groups,
                          const std::function<void(std::size_t)>& fill,
                          std::size_t keep[kContactsPerPatch]);

// The reduction of one collider pair whose contacts all share one normal (a sphere tree on the
// floor plane), made as the contacts are found instead of after: the narrow phase hands each
// leaf contact's point, depth and leaf to add() instead of storing a whole Contact, and
// finish() appends exactly what reducePairContacts would make of those contacts, bit for bit
// (tests/sim/contact_reduction_test.cpp compares the two).
class PlanePatch {
 public:
  void start(const Vec3& normal);  // a new pair; normal: every contact's (on body a)
  // Inline: called once per leaf contact in the narrow phase's hottest loop, so it only stores
  // (the patch sum and the deepest contact are found in finish(), in the same order).
  void add(const Vec3& point, double depth, std::uint32_t leaf) {
    points_.push_back(point);
    depths_.push_back(depth);
    leaves_.push_back(leaf);
  }
  void finish(int a, int b, std::vector<Contact>& out);  // leafB of every contact is 0
  std::size_t size() const { return points_.size(); }    // contacts added since start()

 private:
  Vec3 normal_ = Vec3::UnitZ();
  std::vector<Vec3> points_;
  std::vector<double> depths_;
  std::vector<std::uint32_t> leaves_;
};

}  // namespace vf

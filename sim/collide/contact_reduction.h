// Contact reduction: a few representative contacts per body pair instead of every colliding
// leaf-sphere pair (an extension; the paper is silent on combining leaf contacts, digest
// section 4). Selected by WorldDef::contactReduction / [simulation] contact_reduction.
#pragma once

#include <cstddef>
#include <cstdint>
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
  std::vector<Eigen::Vector2d> flat_;
};

}  // namespace vf

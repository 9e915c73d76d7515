// Contact reduction: a few representative contacts per body pair instead of every colliding
// leaf-sphere pair (an extension; the paper is silent on combining leaf contacts, digest
// section 4). Selected by WorldDef::contactReduction / [simulation] contact_reduction.
#pragma once

#include <cstdint>
#include <vector>

#include "sim/collide/contact.h"

namespace vf {

// Most contacts kept per patch: the deepest plus three that span the patch (Bullet keeps 4).
constexpr int kContactsPerPatch = 4;

// Replaces the contacts of each body pair (consecutive runs with the same a and b, as
// findContacts emits them) by representatives, in place; see contact_reduction.cpp. A patch of
// at most kContactsPerPatch contacts is kept unchanged, so a single contact is still solved by
// eq. 15 exactly. Returns nothing; the order stays deterministic.
void reduceContacts(std::vector<Contact>& contacts);

}  // namespace vf

// Islands: bodies joined, directly or through others, by contacts between two moving bodies.
// The ground, static bodies and sleepers join nothing (they take no impulse), so a pile on the
// floor is as many islands as it has groups of bodies that touch each other. Used by sleeping
// (an island falls asleep as a whole) and by the solver (islands share no moving body, so each
// is solved on its own, on any thread, with the same bits).
#pragma once

#include <vector>

#include "sim/collide/contact.h"
#include "sim/core/body.h"

namespace vf {

// root[i] = the lowest body id of body i's island (i itself for a body that touches no moving
// body, and for bodies that do not move). Deterministic: a function of the contacts' bodies.
void islandRoots(const std::vector<Contact>& contacts, const std::vector<BodyInfo>& bodies,
                 std::vector<int>& root);

}  // namespace vf

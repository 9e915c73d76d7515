// Broad phase: body pairs whose bounding spheres overlap (fig. 3, step 1).
#pragma once

#include <vector>

#include "sim/collide/contact.h"
#include "sim/core/body.h"

namespace vf {

// Appends to `pairs` every pair (a < b) of active bodies, not both static, whose bounding
// spheres (SphereTree::boundingRadius about the centre of mass, each widened by its
// roundingSlack) overlap, found by sweep and prune along x. Ordered by (a, b), so contacts are
// generated in a fixed order.
void findPairs(const std::vector<BodyInfo>& bodies, const std::vector<BodyState>& states,
               std::vector<BodyPair>& pairs);

}  // namespace vf

// Broad phase: body pairs whose bounding spheres overlap (fig. 3, step 1).
#pragma once

#include <algorithm>
#include <vector>

#include "sim/collide/contact.h"
#include "sim/core/body.h"

namespace vf {

// Appends to `pairs` every pair (a < b) of active bodies, not both static, whose bounding
// spheres (SphereTree::boundingRadius about the centre of mass, each widened by its
// roundingSlack) overlap, found by sweep and prune along x within strips along y (and across
// neighbouring strips). Ordered by (a, b), so contacts are generated in a fixed order.
// `order`, if given, is scratch kept from call to call (the last call's sweep order): it makes
// the sweep's sort nearly linear while the bodies move little; the pairs do not depend on it.
void findPairs(const std::vector<BodyInfo>& bodies, const std::vector<BodyState>& states,
               std::vector<BodyPair>& pairs, std::vector<int>* order = nullptr);

// The sweep itself, for any x intervals: sorts `spans` (each with members lo, hi and id) by
// (lo, id) and calls visit(u, v) for every two spans whose intervals overlap, u sorted before
// v. The calls and their order depend on the spans alone. The clearance step rule
// (solve/time_step.cpp, intervals grown by how far a body can move) sweeps with it.
template <class Span, class Visit>
void sweepAlongX(std::vector<Span>& spans, Visit&& visit) {
  std::sort(spans.begin(), spans.end(), [](const Span& u, const Span& v) {
    return u.lo < v.lo || (u.lo == v.lo && u.id < v.id);
  });
  for (std::size_t i = 0; i < spans.size(); ++i)
    for (std::size_t j = i + 1; j < spans.size() && spans[j].lo <= spans[i].hi; ++j)
      visit(spans[i], spans[j]);
}

}  // namespace vf

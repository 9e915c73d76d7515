// Sweep and prune over the bounding spheres along x. Sorting the active bodies by the left
// end of their x interval and sweeping finds every overlapping interval pair in
// O(n log n + overlaps) instead of the O(n^2) all-pairs test that the first version used (fine
// for the paper's dozens of bodies, too slow for a thousand rocks). The sort key ties are broken
// by body id and the output is sorted by (a, b), so the pairs, and hence the contacts, come out
// in exactly the order the all-pairs loop gave: the trajectory does not depend on the method.
#include "sim/collide/broad_phase.h"

#include <algorithm>

namespace vf {

void findPairs(const std::vector<BodyInfo>& bodies, const std::vector<BodyState>& states,
               std::vector<BodyPair>& pairs) {
  struct Interval {
    double lo, hi;
    double reach;  // bounding radius plus the body's rounding slack
    int id;
  };
  std::vector<Interval> xs;
  xs.reserve(bodies.size());
  for (int i = 0; i < static_cast<int>(bodies.size()); ++i) {
    if (!bodies[i].active) continue;
    const double r = bodies[i].shape->tree->boundingRadius;
    const double reach = r + roundingSlack(states[i].x, r);
    xs.push_back({states[i].x.x() - reach, states[i].x.x() + reach, reach, i});
  }
  const std::size_t first = pairs.size();
  sweepAlongX(xs, [&](const Interval& u, const Interval& v) {
    const int a = u.id, b = v.id;
    if (bodies[a].isStatic && bodies[b].isStatic) return;
    const double reach = u.reach + v.reach;
    if ((states[a].x - states[b].x).squaredNorm() < reach * reach)
      pairs.push_back({std::min(a, b), std::max(a, b)});
  });
  std::sort(
      pairs.begin() + static_cast<std::ptrdiff_t>(first), pairs.end(),
      [](const BodyPair& u, const BodyPair& v) { return u.a < v.a || (u.a == v.a && u.b < v.b); });
}

}  // namespace vf

// Sweep and prune over the bounding spheres along x, in strips along y. Sorting the active
// bodies by the left end of their x interval and sweeping finds every overlapping interval pair
// in O(n log n + overlaps) instead of the O(n^2) all-pairs test that the first version used
// (fine for the paper's dozens of bodies, too slow for a thousand rocks); the strips keep the
// overlaps visited to bodies that are also near in y. The sort key ties are broken by body id
// and the output is sorted by (a, b), so the pairs, and hence the contacts, come out in exactly
// the order the all-pairs loop gave: the trajectory does not depend on the method.
#include "sim/collide/broad_phase.h"

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace vf {

void findPairs(const std::vector<BodyInfo>& bodies, const std::vector<BodyState>& states,
               std::vector<BodyPair>& pairs) {
  // Strips along y, as wide as the largest reach sum: two bodies whose spheres overlap lie in
  // the same strip or in neighbouring ones. The sweep along x then runs within each strip and
  // across each pair of neighbouring strips, instead of over everything: with 1,000 rocks
  // spread over the cliff, 19,000 interval overlaps a step were visited for 840 pairs, most of
  // them rocks far apart in y (the sweep was 70 % of the broad phase).
  struct Interval {
    double lo, hi;
    double reach;  // bounding radius plus the body's rounding slack
    int id;
    std::int64_t strip;
  };
  std::vector<Interval> xs;
  xs.reserve(bodies.size());
  double widest = 0, yMin = INFINITY;
  for (int i = 0; i < static_cast<int>(bodies.size()); ++i) {
    if (!bodies[i].active) continue;
    const double r = bodies[i].shape->tree->boundingRadius;
    const double reach = r + roundingSlack(states[i].x, r);
    xs.push_back({states[i].x.x() - reach, states[i].x.x() + reach, reach, i, 0});
    widest = std::max(widest, reach);
    yMin = std::min(yMin, states[i].x.y());
  }
  // Overlapping spheres are less than 2 * widest apart in y; the allowance keeps rounding in
  // the strip index from ever putting two of them two strips apart.
  const double width = 2 * widest * (1 + 1e-9);
  if (width > 0 && std::isfinite(width))
    for (Interval& v : xs) {
      const double strip = std::floor((states[v.id].x.y() - yMin) / width);  // >= 0
      v.strip = strip < 1e15 ? static_cast<std::int64_t>(strip) : std::int64_t{1000000000000000};
    }
  std::sort(xs.begin(), xs.end(), [](const Interval& u, const Interval& v) {
    return u.strip < v.strip ||
           (u.strip == v.strip && (u.lo < v.lo || (u.lo == v.lo && u.id < v.id)));
  });
  const std::size_t first = pairs.size();
  auto test = [&](const Interval& u, const Interval& v) {
    const int a = u.id, b = v.id;
    if (bodies[a].isStatic && bodies[b].isStatic) return;
    const double reach = u.reach + v.reach;
    if ((states[a].x - states[b].x).squaredNorm() < reach * reach)
      pairs.push_back({std::min(a, b), std::max(a, b)});
  };
  auto before = [](const Interval& u, const Interval& v) {
    return u.lo < v.lo || (u.lo == v.lo && u.id < v.id);
  };
  const std::size_t n = xs.size();
  for (std::size_t b = 0; b < n;) {
    std::size_t e = b;
    while (e < n && xs[e].strip == xs[b].strip) ++e;
    // Within the strip: the plain sweep.
    for (std::size_t i = b; i < e; ++i)
      for (std::size_t j = i + 1; j < e && xs[j].lo <= xs[i].hi; ++j) test(xs[i], xs[j]);
    // Across to the next strip: both lists in x order, merged; each overlapping pair is found
    // from the one that comes first, scanning the other list from where it has got to.
    std::size_t e2 = e;
    while (e2 < n && xs[e2].strip == xs[b].strip + 1) ++e2;
    for (std::size_t i = b, j = e; i < e && j < e2;) {
      if (before(xs[i], xs[j])) {
        for (std::size_t k = j; k < e2 && xs[k].lo <= xs[i].hi; ++k) test(xs[i], xs[k]);
        ++i;
      } else {
        for (std::size_t k = i; k < e && xs[k].lo <= xs[j].hi; ++k) test(xs[k], xs[j]);
        ++j;
      }
    }
    b = e;
  }
  std::sort(
      pairs.begin() + static_cast<std::ptrdiff_t>(first), pairs.end(),
      [](const BodyPair& u, const BodyPair& v) { return u.a < v.a || (u.a == v.a && u.b < v.b); });
}

}  // namespace vf

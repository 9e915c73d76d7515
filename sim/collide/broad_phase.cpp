// Sweep and prune over the bounding spheres along x, in strips along y. Sorting the active
// bodies by the left end of their x interval and sweeping finds every overlapping interval pair
// in O(n log n + overlaps) instead of the O(n^2) of an all-pairs test (fine for the paper's
// dozens of bodies, too slow for a thousand rocks); the strips keep the overlaps visited to
// bodies that are also near in y. The sort key ties are broken by body id and the output is
// sorted by (a, b), so the pairs, and hence the contacts, come out in exactly the order an
// all-pairs loop gives: the trajectory does not depend on the method.
#include "sim/collide/broad_phase.h"

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "sim/shape/shape.h"

namespace vf {

void findPairs(const std::vector<BodyInfo>& bodies, const std::vector<BodyState>& states,
               std::vector<BodyPair>& pairs, std::vector<int>* order) {
  // Strips along y, as wide as the largest reach sum: two bodies whose spheres overlap lie in
  // the same strip or in neighbouring ones. The sweep along x then runs within each strip and
  // across each pair of neighbouring strips, instead of over everything: with 1,000 rocks
  // spread over the cliff, a sweep over everything visits 19,000 interval overlaps a step for
  // 840 pairs, most of them rocks far apart in y (70 % of the broad phase).
  struct Interval {
    double lo, hi;
    double reach;  // bounding radius plus the body's rounding slack
    int id;
    std::int64_t strip;
  };
  // Scratch reused from call to call (per thread: ensembles step worlds on several).
  static thread_local std::vector<Interval> xs;
  static thread_local std::vector<char> listed;
  const int count = static_cast<int>(bodies.size());
  xs.clear();
  double widest = 0, yMin = INFINITY;
  auto add = [&](int i) {
    const double r = bodies[i].shape->tree->boundingRadius;
    const double reach = r + roundingSlack(states[i].x, r);
    xs.push_back({states[i].x.x() - reach, states[i].x.x() + reach, reach, i, 0});
    widest = std::max(widest, reach);
    yMin = std::min(yMin, states[i].x.y());
  };
  // The last call's order first (bodies still active), then the others by id. The order the
  // intervals start in changes nothing but how long the sort below takes.
  const bool hinted = order != nullptr && !order->empty();
  if (hinted) {
    listed.assign(count, 0);
    for (int i : *order)
      if (i >= 0 && i < count && bodies[i].active && !listed[i]) listed[i] = 1, add(i);
  }
  for (int i = 0; i < count; ++i)
    if (bodies[i].active && !(hinted && listed[i])) add(i);
  // Overlapping spheres are less than 2 * widest apart in y; the allowance keeps rounding in
  // the strip index from ever putting two of them two strips apart.
  const double width = 2 * widest * (1 + 1e-9);
  if (width > 0 && std::isfinite(width))
    for (Interval& v : xs) {
      const double strip = std::floor((states[v.id].x.y() - yMin) / width);  // >= 0
      v.strip = strip < 1e15 ? static_cast<std::int64_t>(strip) : std::int64_t{1000000000000000};
    }
  auto sorted = [](const Interval& u, const Interval& v) {
    return u.strip < v.strip ||
           (u.strip == v.strip && (u.lo < v.lo || (u.lo == v.lo && u.id < v.id)));
  };
  // A strict total order (ties broken by id): any sort gives the same sequence. From the last
  // step's order the intervals are nearly sorted, and insertion sort is nearly linear (a full
  // sort is a quarter of the broad phase with 1,000 rocks); it gives up for std::sort once it
  // has moved more than a few intervals per interval (a shuffled start).
  bool done = false;
  if (hinted) {
    std::size_t moves = 0;
    const std::size_t budget = 8 * xs.size() + 64;
    done = true;
    for (std::size_t i = 1; i < xs.size() && done; ++i) {
      if (!sorted(xs[i], xs[i - 1])) continue;
      const Interval v = xs[i];
      std::size_t j = i;
      for (; j > 0 && sorted(v, xs[j - 1]); --j) xs[j] = xs[j - 1];
      xs[j] = v;
      moves += i - j;
      done = moves <= budget;
    }
  }
  if (!done) std::sort(xs.begin(), xs.end(), sorted);
  if (order) {
    order->resize(xs.size());
    for (std::size_t i = 0; i < xs.size(); ++i) (*order)[i] = xs[i].id;
  }
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
  // By (a, b): counted out by a, then each a's few partners put in order of b (linear in
  // bodies and pairs; a comparison sort of 1,000 rocks' pairs is a fifth of the broad phase).
  static thread_local std::vector<int> start;
  static thread_local std::vector<BodyPair> found;
  found.assign(pairs.begin() + static_cast<std::ptrdiff_t>(first), pairs.end());
  start.assign(count + 1, 0);
  for (const BodyPair& p : found) ++start[p.a + 1];
  for (int i = 0; i < count; ++i) start[i + 1] += start[i];
  for (const BodyPair& p : found) pairs[first + static_cast<std::size_t>(start[p.a]++)] = p;
  for (std::size_t b = first, e; b < pairs.size(); b = e) {
    for (e = b + 1; e < pairs.size() && pairs[e].a == pairs[b].a;) ++e;
    std::sort(pairs.begin() + static_cast<std::ptrdiff_t>(b),
              pairs.begin() + static_cast<std::ptrdiff_t>(e),
              [](const BodyPair& u, const BodyPair& v) { return u.b < v.b; });
  }
}

}  // namespace vf

// Why the cache outlives a contact's own key in two cases, each an extension's:
//
// Contact reduction keeps a few representatives per patch, chosen afresh every step (the deepest
// point and the extremes of the patch, contact_reduction.cpp). When the bodies shift by a
// fraction of a voxel, the same corner of a patch is carried by a neighbouring leaf pair, whose
// key is new; found by key alone, that representative starts the step from zero although it
// holds a share of everything above it. Twelve Gauss-Seidel passes do not rebuild a pile's
// load from zero, and a resting contact is only stopped, never pushed back (impulse.cpp), so
// each such step lets the pile sag by what the passes missed, for good: piles of boxes dropped
// one by one sank past eq. 17's bound (tests/scenario/pile_drops_test.cpp). So a
// representative that matches no key takes the impulse of last step's nearest unclaimed
// contact of the same body pair, if that lies within reach. Reach: a leaf pair's contact point is
// the midpoint of its two sphere centres (fig. 5), and a neighbouring voxel's centre lies at most a
// voxel diagonal, twice the leaf radius, from a voxel's; so replacing each leaf by a neighbour
// moves the point by at most the sum of the two leaf radii (against the floor or the terrain the
// point follows the one centre, up to twice its radius). Between two steps the bodies themselves
// move less than a leaf radius (eq. 17). Each cached impulse seeds at most one contact, so a pair's
// warm start never exceeds what held it in the last step.
//
// Sleeping stops finding the contacts of an island at rest; when the island wakes, its contacts
// come back with their old keys (nothing moved), but the last step's cache no longer held them,
// so the whole pile would start from zero and sag on every wake, on every drop onto it
// (tests/sim/sleep_test.cpp). So the contacts of sleeping bodies stay in the cache, unchanged,
// for as long as they sleep (keepSleepingContacts).
//
// Alternative rejected: more solver passes. Twice as many also stop the sag of a column of
// boxes, but cost twice the solver's time in every step of every pile, where the cause is an
// impulse thrown away.
#include "sim/solve/contact_cache.h"

#include <algorithm>
#include <cstdio>
#include <cstdlib>

#include "sim/shape/shape.h"

namespace vf {

namespace {

bool keyLess(const CachedImpulse& c, const ContactKey& key) { return c.key < key; }

}  // namespace

std::ptrdiff_t findCached(const ContactCache& cache, const ContactKey& key) {
  const auto it = std::lower_bound(cache.impulses.begin(), cache.impulses.end(), key, keyLess);
  if (it == cache.impulses.end() || it->key != key) return -1;
  return it - cache.impulses.begin();
}

std::ptrdiff_t nearestCached(const ContactCache& cache, int a, int b, const Vec3& point,
                             double reach, const std::vector<char>& claimed) {
  const ContactKey first{a, b, 0, 0};
  auto it = std::lower_bound(cache.impulses.begin(), cache.impulses.end(), first, keyLess);
  std::ptrdiff_t best = -1;
  double bestDistance = reach * reach;
  for (; it != cache.impulses.end() && it->key.a == a && it->key.b == b; ++it) {
    const std::ptrdiff_t i = it - cache.impulses.begin();
    if (claimed[static_cast<std::size_t>(i)]) continue;
    const double d = (it->point - point).squaredNorm();
    if (d <= bestDistance && (best < 0 || d < bestDistance)) {
      best = i;
      bestDistance = d;
    }
  }
  return best;
}

double representativeReach(const BodyInfo& a, const BodyInfo* b) {
  const double ra = a.shape->tree->leaves().radius;
  return b ? ra + b->shape->tree->leaves().radius : 2 * ra;
}

void keepSleepingContacts(const ContactCache& previous, const std::vector<BodyInfo>& bodies,
                          std::vector<CachedImpulse>& kept) {
  auto still = [&](int i) { return i == kGround || !bodies[i].moves(); };
  auto asleep = [&](int i) { return i != kGround && bodies[i].sleeping; };
  for (const CachedImpulse& c : previous.impulses)
    if (still(c.key.a) && still(c.key.b) && (asleep(c.key.a) || asleep(c.key.b))) kept.push_back(c);
}

}  // namespace vf

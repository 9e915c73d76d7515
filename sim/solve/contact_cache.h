// The warm-start cache: each resting contact's impulse, carried from one step to the next so
// that a pile's passes start from the impulses that held it (impulse.cpp says why that
// matters), and which cached impulse seeds a contact of the next step. See contact_cache.cpp.
#pragma once

#include <cstddef>
#include <vector>

#include "sim/collide/contact.h"
#include "sim/core/body.h"

namespace vf {

// A resting contact's accumulated impulse at the end of a step.
struct CachedImpulse {
  ContactKey key;
  double normal = 0, tangent1 = 0, tangent2 = 0;  // N s, along the contact's normal and tangents
  Vec3 impulse = Vec3::Zero();                    // the same impulse as one world vector, N s
  Vec3 point = Vec3::Zero();                      // the contact point, world frame, m
  double dt = 0;                                  // length of the step the impulse belongs to, s
};

struct ContactCache {
  std::vector<CachedImpulse> impulses;  // sorted by key
  std::vector<CachedImpulse> scratch;   // reused while the next step's cache is made
};

// Index of the entry with exactly this key (same body pair, same two leaves), or -1.
std::ptrdiff_t findCached(const ContactCache& cache, const ContactKey& key);

// Index of the entry of body pair (a, b) whose point lies nearest to `point` and within `reach`
// of it, among those not yet claimed (claimed[i] != 0); the first in key order among equals;
// -1 if none. For contact reduction's representatives: see contact_cache.cpp.
std::ptrdiff_t nearestCached(const ContactCache& cache, int a, int b, const Vec3& point,
                             double reach, const std::vector<char>& claimed);

// How far a reduced contact's point may lie from last step's and still stand for the same
// support point (nearestCached's reach): the leaf radii of its two sides, one side's twice
// against the ground (contact_cache.cpp gives the reason), m.
double representativeReach(const BodyInfo& a, const BodyInfo* b);

// The factor a cached impulse is scaled by in a step of length dt: min(1, dt / its step's
// length). Never above 1: part of an impulse corrects velocity errors and does not grow with
// dt (impulse.cpp).
inline double warmStartScale(const CachedImpulse& c, double dt) {
  return c.dt > 0 ? std::min(1.0, dt / c.dt) : 0.0;
}

// Appends to `kept` the entries of `previous` whose contacts no step finds while their bodies
// sleep: both sides still (asleep, static or the ground) and at least one asleep. They seed the
// island's contacts again on the step that wakes it, so a woken pile starts from the impulses
// that held it when it fell asleep instead of from zero.
void keepSleepingContacts(const ContactCache& previous, const std::vector<BodyInfo>& bodies,
                          std::vector<CachedImpulse>& kept);

}  // namespace vf

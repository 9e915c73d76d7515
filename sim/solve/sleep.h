// Sleeping: bodies at rest cost nothing until something touches them (an extension; the paper
// steps every body every step). Selected by WorldDef::sleep / [simulation] sleep.
#pragma once

#include <vector>

#include "sim/collide/contact.h"
#include "sim/core/body.h"

namespace vf {

struct SleepSettings {
  // A body is at rest while it touches something (another body, the ground) and v + (l/2) w,
  // the fastest speed of any of its points (eq. 18's v_max for one body), stays below `speed`
  // (m/s)...
  double speed = 0.05;
  // ...for `time` seconds in a row. An island (bodies joined by contacts, ground and static
  // bodies excluded) falls asleep when all its bodies have rested that long.
  double time = 0.5;
};

// Wakes every sleeping body that a contact joins to a moving body, together with the island
// it fell asleep with (their momenta are zero: they start from rest). Returns the ids of the
// bodies woken, ascending.
std::vector<int> wakeTouched(const std::vector<Contact>& contacts, std::vector<BodyInfo>& bodies);

// After a step of length dt: advances each moving body's rest time (reset when it moves
// faster than the threshold), then puts to sleep every island whose bodies have all rested
// for settings.time, zeroing their momenta. Islands come from this step's contacts. Returns the
// bodies that fell asleep.
int updateSleep(const std::vector<Contact>& contacts, std::vector<BodyInfo>& bodies,
                std::vector<BodyState>& states, double dt, const SleepSettings& settings);

}  // namespace vf

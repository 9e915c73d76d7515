// Frames between steps. A frame at time t is taken from the two step states that bracket it
// (the last at or before t, the first after it): positions and momenta interpolated linearly,
// orientations by slerp on the short arc. So a frame at a step time is that step's state to the
// bit, a body at rest in both steps is at rest in the frame, and nothing is simulated: no
// gravity or contact is applied between steps. The recorder (sim/recorder.h) and a bake's
// reader (sim/bake.h) both sample through sampleSteps, so a bake draws the frames its run wrote.
#pragma once

#include <vector>

#include "sim/core/body.h"
#include "sim/core/math.h"

namespace vf {

// Every body's state and released flag right after one step (or before the first).
struct StepState {
  double time = 0;                // s
  std::vector<BodyState> states;  // per body id
  std::vector<char> active;       // per body id: released (and not removed)
};

// The orientation a fraction s (0..1) of the way from a to b along the great arc, the short one
// (b's sign flipped where a.b < 0: q and -q are the same rotation). Returns a itself, to the
// bit, for s = 0 or b == a.
Quat slerpShortArc(const Quat& a, const Quat& b, double s);

// One body between its states a (s = 0) and b (s = 1): x, P and L as a + s (b - a) (equal
// values stay equal to the bit), q by slerpShortArc.
BodyState interpolateBody(const BodyState& a, const BodyState& b, double s);

// The frame at t from the step state `before` (time <= t + kTimeTolerance) and the next one
// `after` (null where the run has no further step: the frame then holds `before`). A frame
// within kTimeTolerance of a step time is that step's state. Bodies take `before`'s released
// flags (one released by the step that ends at after->time is not there yet), and a body not
// active in both states holds its `before` state (a release or a removal happens at the end of
// a step, not along it). `active` receives the frame's flags.
std::vector<BodyState> sampleSteps(const StepState& before, const StepState* after, double t,
                                   std::vector<char>& active);

}  // namespace vf

// The step-size rule of section 4 (eqs. 17-20).
#pragma once

#include <vector>

#include "sim/core/body.h"

namespace vf {

// The largest step at which no leaf sphere of a moving body moves more than its own radius
// (eq. 17), for the current state, capped at maxStep. See time_step.cpp for the details.
double stableStep(const std::vector<BodyInfo>& bodies, const std::vector<BodyState>& states,
                  const Vec3& gravity, double maxStep);

// The length of the next step towards `remaining` seconds ahead: the rule (the fixed step if
// fixedStep > 0, else `stable`, the eq.-20 step, raised to minStep if a runaway body asks for
// less: then `floored` is set), split so that the interval is covered by equal steps none
// longer than the rule. `lands` is set when this step reaches the end of the interval exactly.
// An infinite `remaining` (no target) gives the rule's step.
double chooseStep(double remaining, double fixedStep, double stable, double minStep, bool& lands,
                  bool& floored);

}  // namespace vf

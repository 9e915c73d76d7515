// The step-size rule of section 4 (eqs. 17-20).
#pragma once

#include <vector>

#include "sim/core/body.h"
#include "sim/world.h"

namespace vf {

// The largest step at which no leaf sphere of a moving body moves more than its own radius
// (eq. 17), for the current state, capped at maxStep. See time_step.cpp for the details.
double stableStep(const std::vector<BodyInfo>& bodies, const std::vector<BodyState>& states,
                  const Vec3& gravity, double maxStep);

}  // namespace vf

// Refusing a run before it starts: a body faster than the speed bound, or a run that the step
// rule would make longer than the step limit (run_length.cpp). The checks during a run are
// the RunGuard's (run_guard.h).
#pragma once

#include <string>
#include <vector>

#include "sim/run_guard.h"
#include "sim/world.h"

namespace vf {

// Refuses (InputError at where[id]) a run of `duration` seconds in which a body starts faster
// than limits.maxSpeed, or would need more than limits.maxSteps steps by the step rule (eq. 20,
// the fixed step, and the world's step bounds). `where` holds one location per body id.
void checkRunLength(const World& world, double duration, const RunLimits& limits,
                    const std::vector<std::string>& where);

// Steps the world's step rule would take for body `id` alone over `duration` seconds if it fell
// freely from its initial state the whole time (an upper bound for a body that lands).
double estimatedSteps(const World& world, int id, double duration);

}  // namespace vf

// Rolling resistance at ground contacts (rock fall extension; opt-in per ground material).
#pragma once

#include <vector>

#include "sim/collide/contact.h"
#include "sim/core/body.h"
#include "sim/ground/ground_material.h"

namespace vf {

// Runs after solveContacts with the normal impulse of every contact (N s, in contact order).
// Per body, its ground contacts (b == kGround) with a material of rolling resistance mu_r > 0
// give an angular impulse opposing the rolling part of the spin, w_t = w - (w.n)n (n: the
// impulse-weighted mean normal), of magnitude min(|w_t| / (t.I^-1 t), sum_k mu_r,k h_k jn_k)
// with t = w_t / |w_t| and h_k = -(r_k . n_k) the lever of contact k (the centre of mass's
// height above it): a torque mu_r h N, which can stop a rolling body but never reverse it.
// Returns the number of bodies it braked.
int applyRollingResistance(const std::vector<Contact>& contacts,
                           const std::vector<double>& normalImpulses,
                           const std::vector<BodyInfo>& bodies, std::vector<BodyState>& states,
                           const GroundMap& ground);

}  // namespace vf

// Slippage-dependent friction of the RAMMS-type ground law (rock fall extension; opt-in per
// ground material, law = "slip"): the per-body slippage s that the solver's mu(s) reads
// (slip_law.cpp).
#pragma once

#include <vector>

#include "sim/collide/contact.h"
#include "sim/core/body.h"
#include "sim/ground/ground_material.h"

namespace vf {

// Per-body slippage s (m), kept across steps; 0 at release.
class SlipLaw {
 public:
  // Sizes the per-body state for `bodies` bodies (new ones start at s = 0).
  void resize(std::size_t bodies);
  // s per body, m: what the solver's friction of slip-material contacts reads (mu(s),
  // slipFriction) during the step.
  const std::vector<double>& slippage() const { return s_; }

  // Leine et al. 2014 eq. 47 over the step just solved, per moving body: if one of its ground
  // contacts on a slip material carries normal impulse (N s, in contact order), s grows by the
  // centre of mass's path |v| dt (v after the solve: the velocity the step moves it by);
  // otherwise s decays by exp(-beta dt), with beta that of the slip contact with the largest
  // normal impulse in its last step on slip ground.
  void afterSolve(const std::vector<Contact>& contacts, const std::vector<double>& normalImpulses,
                  const std::vector<BodyInfo>& bodies, const std::vector<BodyState>& states,
                  const GroundMap& ground, double dt);

 private:
  std::vector<double> s_;     // slippage, m
  std::vector<double> beta_;  // decay rate of the last step on slip ground, 1/s
  // Per-step scratch, per body: the largest normal impulse of a slip contact (N s; 0: none)
  // and that contact's beta.
  std::vector<double> largest_, stepBeta_;
};

}  // namespace vf

// What an extension of the step sees and when (as Jolt's PhysicsStepListener): the World calls
// each attached listener at fixed points of its step, in the order attached, so a policy that
// is not the paper's method (rock fall's ground laws and monitor, the run guard) acts on the
// bodies without the step naming it. A listener holds its own settings and per-body state; the
// context hands it the body arrays of the step it is called in.
#pragma once

#include <optional>
#include <vector>

#include "sim/collide/contact.h"
#include "sim/core/body.h"
#include "sim/core/runaway.h"

namespace vf {

struct SolverSettings;  // sim/solve/impulse.h

// The world's arrays and clock at a call. Listeners may change the states (and the bodies'
// flags, as the rock monitor's edge policy does) but never add or remove bodies.
struct StepContext {
  std::vector<BodyInfo>& bodies;
  std::vector<BodyState>& states;
  const std::vector<Contact>& contacts;  // the step's contacts (in onRelease: the last step's)
  double time;  // s: the step's start up to beforeMove, its end from afterIntegrate on
  double dt;    // s: the step's length; 0 in onRelease
};

class StepListener {
 public:
  virtual ~StepListener() = default;

  // Just before the contact solve: may hand the solver what it reads (SolverSettings'
  // ground map, slippage and normal-impulse output).
  virtual void beforeSolve(StepContext& /*c*/, SolverSettings& /*solver*/) {}
  // Just after the contact solve, momenta final but positions not yet moved.
  virtual void afterSolve(StepContext& /*c*/) {}
  // After afterSolve of every listener, before anything moves: a Runaway stops the run (the
  // World takes no more steps, keeps the state as it is and throws RunawayError with it).
  virtual std::optional<Runaway> beforeMove(const StepContext& /*c*/) { return std::nullopt; }
  // After the integration, before the sleep update.
  virtual void afterIntegrate(StepContext& /*c*/) {}
  // Dynamic or static body `id` has just joined the world: at addBody when it is active at
  // once, or at its release time (after its placement, before the next body's).
  virtual void onRelease(StepContext& /*c*/, int /*id*/) {}
  // After the step's releases, before the step's stats are kept and its state is hashed.
  virtual void afterStep(StepContext& /*c*/) {}
};

}  // namespace vf

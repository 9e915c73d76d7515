// Runaway physics stops with a reason. During a run the RunGuard, attached to every World as a
// step listener (RunGuardListener) and called once per step, stops the run at the first non-finite
// state, body faster than the bound, or rise of the total energy beyond what gravity and the energy
// the bodies started with allow (see run_guard.cpp for the rules and their margins). Before a run,
// checkRunLength() (run_length.h) refuses bodies that would need more steps than a limit or that
// start faster than the bound.
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "sim/core/body.h"
#include "sim/core/math.h"
#include "sim/core/runaway.h"
#include "sim/solve/step_listener.h"

namespace vf {

struct BodyState;

struct RunLimits {
  std::uint64_t maxSteps = 10'000'000;  // steps a run may need (estimated before it starts)
  double maxSpeed = 1000;               // m/s, of a body's fastest point: |v| + (l/2) |w|
  double energyMargin = 0.5;            // allowed energy gain, as a fraction of the energy scale
};

// Per-run bookkeeping of the energy budget. check() is called after the impulses of every step
// (momenta final for the step, positions not yet moved).
class RunGuard {
 public:
  // Returns what stopped the run, or nothing. `time` is the start of the step (s).
  // Energies are those of the state the step will produce: the momenta as they are, the
  // positions moved by dt (x + dt P / m, as the integrator will move them).
  std::optional<Runaway> check(const std::vector<BodyInfo>& bodies,
                               const std::vector<BodyState>& states, const Vec3& gravity,
                               double time, double dt, const RunLimits& limits);
  // Largest energy gain seen so far, as a fraction of the scale (what energyMargin bounds).
  double peakGainRatio() const { return peakGainRatio_; }

 private:
  std::vector<char> counted_;    // bodies whose release energy is in the budget
  double releaseEnergy_ = 0;     // J, sum of E_i (kinetic + potential) at release
  double releasePotential_ = 0;  // J, sum of the potential energies at release
  double scale_ = 0;             // J, sum of (kinetic energy at release + m |g| l)
  double peakGainRatio_ = 0;
};

// The guard attached to a World (every World has one): checks each step before anything moves.
class RunGuardListener : public StepListener {
 public:
  RunGuardListener(const RunLimits& limits, const Vec3& gravity);
  std::optional<Runaway> beforeMove(const StepContext& c) override;
  const RunGuard& guard() const { return guard_; }

 private:
  RunGuard guard_;
  RunLimits limits_;
  Vec3 gravity_;
};

}  // namespace vf

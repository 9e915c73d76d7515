// Runaway physics stops with a reason. During a run the RunGuard, called once per step by
// World, stops the run at the first non-finite state, body faster than the bound, or rise of
// the total energy beyond what gravity and the energy the bodies started with allow (see
// run_guard.cpp for the rules and their margins). Before a run, checkRunLength()
// (run_length.h) refuses bodies that would need more steps than a limit or that start faster
// than the bound.
#pragma once

#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "sim/core/body.h"
#include "sim/core/math.h"

namespace vf {

struct BodyState;

struct RunLimits {
  std::uint64_t maxSteps = 10'000'000;  // steps a run may need (estimated before it starts)
  double maxSpeed = 1000;               // m/s, of a body's fastest point: |v| + (l/2) |w|
  double energyMargin = 0.5;            // allowed energy gain, as a fraction of the energy scale
};

// Why a run was stopped.
struct Runaway {
  int body = -1;         // the body concerned
  std::string shape;     // its shape's name
  double time = 0;       // s, the step during which it happened began here
  std::string quantity;  // "non-finite state", "speed", "energy"
  double value = 0;      // the measured value (m/s, J); NaN for a non-finite state
  double limit = 0;      // the bound it crossed
  // One line: "body 3 at t = 1.25 s: speed 4.5e4 m/s exceeds the limit of 1000 m/s; ...".
  std::string message() const;
};

// Thrown by World::step, stepNext and advanceTo when the guard stopped the run; the state is that
// of the step in which the trouble was found, before the bodies moved.
class RunawayError : public std::runtime_error {
 public:
  explicit RunawayError(const Runaway& r);
  const Runaway& runaway() const { return runaway_; }

 private:
  Runaway runaway_;
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

// The wording of the guard's messages, shared with run_length.cpp's: a number to 4 significant
// digits, and "body 3 (shape 'rock')".
std::string guardNumber(double x);
std::string guardBodyName(int id, const std::string& shape);

}  // namespace vf

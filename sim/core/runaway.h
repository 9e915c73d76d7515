// Why a run was stopped, and the error World's step throws with it (the run guard,
// sim/run_guard.h, decides; callers catch RunawayError without seeing the guard).
#pragma once

#include <stdexcept>
#include <string>

namespace vf {

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

// The wording of the guard's messages, shared with run_length.cpp's: a number to 4 significant
// digits, and "body 3 (shape 'rock')".
std::string guardNumber(double x);
std::string guardBodyName(int id, const std::string& shape);

}  // namespace vf

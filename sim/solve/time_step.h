// The step-size rule of section 4 (eqs. 17-20).
#pragma once

#include <optional>
#include <vector>

#include "sim/core/body.h"

namespace vf {

struct Heightfield;  // sim/shape/heightfield.h

// Which rule sets each step's length (scene key `[simulation] step`): eq. 20, the paper's; the
// clearance rule, an extension that changes trajectories (clearanceStep below); or a fixed step.
struct StepRule {
  enum class Kind { kEq20, kClearance, kFixed };
  Kind kind = Kind::kEq20;
  double seconds = 0;  // the fixed step, s (kFixed only)

  static StepRule eq20() { return {}; }
  static StepRule clearance() { return {Kind::kClearance, 0}; }
  static StepRule fixed(double s) { return {Kind::kFixed, s}; }
  bool isFixed() const { return kind == Kind::kFixed; }
  bool isClearance() const { return kind == Kind::kClearance; }
};

// The largest step at which no leaf sphere of a moving body, or of an asleep one woken within
// the step, moves more than its own radius (eq. 17), for the current state, capped at maxStep.
// See time_step.cpp for the details.
double stableStep(const std::vector<BodyInfo>& bodies, const std::vector<BodyState>& states,
                  const Vec3& gravity, double maxStep);

// The clearance rule, an extension (`[simulation] step = "clearance"`): eq. 17 asked only of
// bodies that could touch something within the step; a body farther than that from everything
// may move up to its share of the distance. Never shorter than stableStep. Needs the floor
// plane (z = groundHeight, if any) and the terrain (if any). See time_step.cpp.
double clearanceStep(const std::vector<BodyInfo>& bodies, const std::vector<BodyState>& states,
                     const Vec3& gravity, double maxStep, const std::optional<double>& groundHeight,
                     const Heightfield* terrain);

// The length of the next step towards `remaining` seconds ahead: the rule (the fixed step if
// fixedStep > 0, else `stable`, the eq.-20 step, raised to minStep if a runaway body asks for
// less: then `floored` is set), split so that the interval is covered by equal steps none
// longer than the rule. `lands` is set when this step reaches the end of the interval exactly.
// An infinite `remaining` (no target) gives the rule's step.
double chooseStep(double remaining, double fixedStep, double stable, double minStep, bool& lands,
                  bool& floored);

}  // namespace vf

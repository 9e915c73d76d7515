// Per-body constants beside the mutable BodyState array: what the step stages read.
#pragma once

#include <memory>

#include "sim/core/math.h"
#include "sim/shape/shape.h"

namespace vf {

struct BodyInfo {
  std::shared_ptr<const Shape> shape;
  double invMass = 0;                   // 1/M, 0 for static bodies
  Mat3 inertiaBodyInv = Mat3::Zero();   // I_body^-1, zero for static bodies
  bool isStatic = false;
  bool active = true;                   // released (emitter bodies join later)
  double releaseTime = 0;               // s
  double dropHeight = -1;               // m; < 0: release where placed (see BodyDef)
  bool moves() const { return active && !isStatic; }
};

}  // namespace vf

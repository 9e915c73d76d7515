// Per-cell factors for ground coefficients (why, and how they differ from r.stone's: the header).
#include "sim/ground/ground_variability.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "sim/core/hash.h"
#include "sim/core/prng.h"

namespace vf {

double variabilityFactor(std::uint64_t seed, std::int64_t cell, GroundCoefficient which,
                         double bound) {
  // One stream per (seed, cell, coefficient), so that no coefficient's draws depend on which
  // others the law uses, nor on the order in which cells are met.
  Hasher h;
  h.add(seed);
  h.add(static_cast<std::uint64_t>(cell));
  h.add(static_cast<std::uint64_t>(which));
  Prng rng(h.value());
  // Box-Muller, one variate per pair of uniforms; redrawn outside [-2, 2] (4.6 % of draws).
  while (true) {
    const double u1 = rng.uniform(), u2 = rng.uniform();
    if (u1 == 0.0) continue;  // log(0)
    const double z = std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * std::numbers::pi * u2);
    if (std::abs(z) <= 2.0) return 1.0 + 0.5 * bound * z;
  }
}

GroundCoefficients perturbedCoefficients(const GroundCoefficients& c, double bound,
                                         std::uint64_t seed, std::int64_t cell) {
  GroundCoefficients p = c;
  auto scale = [&](double& v, GroundCoefficient which) {
    v *= variabilityFactor(seed, cell, which, bound);
  };
  scale(p.restitution, GroundCoefficient::kRestitution);
  p.restitution = std::min(p.restitution, 1.0);
  if (c.law == GroundLawKind::kSlip) {
    scale(p.muMin, GroundCoefficient::kMuMin);
    scale(p.muMax, GroundCoefficient::kMuMax);
    p.muMax = std::max(p.muMax, p.muMin);
    scale(p.kappa, GroundCoefficient::kKappa);
    scale(p.beta, GroundCoefficient::kBeta);
  } else {
    scale(p.friction, GroundCoefficient::kFriction);
    scale(p.rollingResistance, GroundCoefficient::kRollingResistance);
    scale(p.tangentialRestitution, GroundCoefficient::kTangentialRestitution);
    p.tangentialRestitution = std::min(p.tangentialRestitution, 1.0);
  }
  return p;
}

}  // namespace vf

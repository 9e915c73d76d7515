// Which orientation update the integrator uses (solve/integrate.cpp).
#pragma once

namespace vf {

// How q is advanced (the paper: explicit Euler on eq. 7).
enum class RotationUpdate {
  kExplicitEuler,  // q += dt (1/2) [0, w] q, renormalised: the paper's; gains energy in free
                   // tumbling (+6.2 % for analytic_test's box over 10 s at dt = 1e-3)
  kMidpoint,       // q rotated exactly by w_mid dt, w_mid = I(t_mid)^-1 L at the orientation
                   // half a step on: second order, keeps |q| = 1 and the energy of free
                   // tumbling within 1 % (tests/scenario/analytic_test.cpp)
};

}  // namespace vf

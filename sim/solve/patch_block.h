// The pseudo-inverse of a patch block: the normal impulses of a reduced patch's 2-4 points
// solved together (SolverSettings::patchBlocks; impulse.cpp says why).
#pragma once

#include "sim/core/math.h"

namespace vf {

// The Moore-Penrose pseudo-inverse of a patch block (the top left m x m of `block`, m = 2..4,
// K_ij = the normal velocity at point i per unit normal impulse at point j, all along the
// patch's normal n; SolverSettings::patchBlocks) into the top left m x m of `inverse`. `arms`:
// the points' r_a x n. By a closed form where K is well conditioned but for the null direction
// that four coplanar points always give it (returns true), else by an eigen-decomposition that
// leaves out eigenvalues below 1e-9 of the largest. See patch_block.cpp.
bool patchBlockInverse(const Eigen::Matrix4d& block, int m, const Vec3* arms, const Vec3& n,
                       Eigen::Matrix4d& inverse);

}  // namespace vf

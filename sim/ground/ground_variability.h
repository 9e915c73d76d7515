// Per-cell variability of ground coefficients for ensembles, after r.stone: each coefficient of
// a material is scaled, per DEM cell, by a seeded random factor within 1 +- bound.
//
// What r.stone does and what voxfall does instead. The r.stone manual (OSGeo grass-addons,
// src/raster/r.stone/r.stone.md) describes "cell-by-cell values of restitution and friction
// coefficients extracted from Gaussian distributions centered on the values specified in the
// corresponding input raster and limited by +/- 10% from the central value". Its code
// (utils.c, GetRandVElas and siblings; random2.c) does something else: at every bounce or roll
// step it draws a Gaussian of standard deviation 2 x 0.10 in absolute units (not relative)
// around the cell's value and clips the result to [0, 1]; nothing bounds it to 10 %. voxfall
// implements the manual's description, which is the documented model:
//  - one factor per (DEM sample's cell, coefficient), fixed for the run (an ensemble
//    realisation draws its own seed), so a rock crossing the same cell twice meets the same
//    ground;
//  - the factor is 1 + (bound / 2) z, z a standard Gaussian truncated to [-2, 2] by redrawing:
//    every value lies within +-bound of the material's, and 95 % of untruncated draws would
//    already. The standard deviation bound / 2 is voxfall's choice: the manual gives the limit,
//    not the spread;
//  - relative, so a zero coefficient (the slip presets' eps_N) stays zero; a restitution or
//    tangential restitution scaled past 1 is clipped to 1 (as r.stone clips), and a mu_max
//    drawn below the cell's mu_min is raised to it (mu(s) must not fall with s).
// Each factor is a pure function of (seed, cell, coefficient): any thread, any order, the same
// numbers, with no table to build or share.
#pragma once

#include <cstdint>

#include "sim/ground/ground_material.h"

namespace vf {

// The coefficients a perturbation scales, one random stream each.
enum class GroundCoefficient {
  kRestitution,
  kFriction,
  kRollingResistance,
  kTangentialRestitution,
  kMuMin,
  kMuMax,
  kKappa,
  kBeta
};

// The factor of coefficient `which` in DEM cell `cell` for `seed`: 1 + (bound / 2) z, z a
// standard Gaussian truncated to [-2, 2]; in [1 - bound, 1 + bound].
double variabilityFactor(std::uint64_t seed, std::int64_t cell, GroundCoefficient which,
                         double bound);

// `c` with every coefficient of its law scaled by its factor in `cell` (stone law: restitution,
// friction, rolling resistance, tangential restitution; slip law: restitution, mu_min, mu_max,
// kappa, beta), restitutions clipped to 1 and mu_max kept >= mu_min.
GroundCoefficients perturbedCoefficients(const GroundCoefficients& c, double bound,
                                         std::uint64_t seed, std::int64_t cell);

}  // namespace vf

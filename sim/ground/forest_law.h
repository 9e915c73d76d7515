// Rocks meeting trees (rock fall extension; opt-in with RockFallDef::forest): after each step,
// every moving body that crossed forest draws whether it met a stem on the way, and a hit takes
// the stem's absorbable energy from it. Owned by the rock-fall step listener (rock_fall.h) like
// the rock monitor; reads and writes the body arrays after the integration.
//
// Statistical, not geometric (docs/rockfall.md, "Forest"): stems are not bodies the sphere tree
// collides with, because the inputs are stand rasters (a density and a mean DBH per cell), which
// place no stem; a geometric model would need stem positions, and would then decide hits by the
// rock's real shape. The statistical model is Rockyfor3D's approach (Dorren 2016, section 3.4):
//  - chance of a hit over the step's horizontal path s through the stand under its midpoint:
//    1 - exp(-n (d + DBH) s) (forest.h), d the diameter of the sphere of the rock's volume;
//  - on a hit the rock loses E = stemEnergy(DBH, species) of its kinetic energy K, taken from
//    translation and spin alike (P and L scaled by sqrt(1 - E / K)), so it keeps its direction
//    and its spin axis; a stem that can absorb all of K stops the rock (P = L = 0). No deflection:
//    the direction change of a hit is left out (Rockyfor3D turns the rock; voxfall does not).
// Deterministic: each body draws from its own stream, a function of the seed and the body id,
// in body order after the (thread-independent) integration, so any thread count gives the same
// hits. A stand of zero density draws nothing and changes nothing.
#pragma once

#include <cstdint>
#include <vector>

#include "sim/core/body.h"
#include "sim/core/prng.h"
#include "sim/ground/forest.h"

namespace vf {

// What the forest did to one body over the run.
struct TreeHits {
  int hits = 0;         // stems met
  double absorbed = 0;  // kinetic energy they took, J
};

class ForestLaw {
 public:
  // After the step's integration: bodies that moved through forest may meet a stem. Returns the
  // number of hits this step.
  int afterStep(const Forest& forest, std::uint64_t seed, const std::vector<BodyInfo>& bodies,
                std::vector<BodyState>& states);
  // Body id's hits so far (zero for a body that met none).
  TreeHits hits(int id) const;

 private:
  struct Track {
    bool seen = false;  // `last` holds the body's position after the previous step
    Vec3 last = Vec3::Zero();
    Prng rng{0};
    TreeHits hits;
  };
  std::vector<Track> tracks_;
};

}  // namespace vf

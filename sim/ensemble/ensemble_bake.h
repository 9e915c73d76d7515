// A chosen subset of an ensemble's realisations as one bake (sim/bake.h), so that
// `voxfall render SUBSET.bake` draws their trajectories together over the terrain.
#pragma once

#include <cstdint>
#include <vector>

#include "sim/bake.h"
#include "sim/ensemble/ensemble.h"

namespace vf {

// One body per realisation of `indices` (in that order), a record at every frame time
// t = k / fps holding each realisation's state at t, sampled from the two steps of that
// realisation's own world that bracket t (its own step sequence, the one Ensemble::run takes;
// sim/frame_interp.h), as the Recorder samples a frame. A realisation
// that ended (stopped, left, buried) keeps its last state; one that left the DEM or was buried
// is inactive from then on. The records run from k = 0 to the first frame at which every
// realisation of the subset has ended, or to floor(duration * fps) if one has not. Bodies get
// distinct colours. `checksums`, when given, receives each realisation's trajectory checksum
// (World::stepsHash after the steps Ensemble::run takes: runs.csv's `checksum`), in the order
// of `indices`.
Bake ensembleBake(const Ensemble& ensemble, std::uint64_t ensembleSeed,
                  const std::vector<std::int64_t>& indices,
                  std::vector<std::uint64_t>* checksums = nullptr);

}  // namespace vf

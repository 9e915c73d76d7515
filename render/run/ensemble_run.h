// An ensemble run as a library call: what `voxfall ensemble SCENE --runs N` does, for the
// command and for any program or test that wants it without argv. Many independent realisations
// of the scene's [ensemble] release (sim/ensemble/), reduced into per-cell rasters on the DEM's
// grid, a table of runs and a summary (docs/ensembles.md).
//
// The run: the journal (sim/ensemble/ensemble_journal.h: every complete realisation appended as
// it completes, so a killed run loses only what was in flight, and --resume continues it), the
// realisations still to run (sim/ensemble/ensemble_shards.h: --resume, --shard), threads and MPI
// ranks, the progress line. The outputs are reduced from the journal in index order
// (render/run/ensemble_files.h), so they are the same bytes for any number of jobs, any number of
// MPI ranks, any interruptions and any split into shards. Outputs and the journal are written by
// rank 0 alone. A run stops as render/run/stop_policy.h says: the files hold the complete
// realisations and the summary says the run was interrupted.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "render/run/ensemble_files.h"
#include "render/run/stop_policy.h"
#include "sim/scene/scene.h"

namespace vf {

struct EnsembleRequest {
  std::string scene;                  // the scene file, with an [ensemble] table
  std::int64_t runs = 0;              // realisations N
  std::optional<std::uint64_t> seed;  // none: [ensemble] seed
  int jobs = 1;                       // threads running realisations
  std::optional<std::int64_t> only;   // run realisation i alone (no journal)
  std::string shard;                  // "i/n": shard i of n, into a journal only
  bool resume = false;                // continue the journal in files.outDir
  EnsembleFileOptions files;          // the output folder and what goes in it
  SceneOverrides overrides;           // level, step, collider, run limits, repair
};

// Runs the realisations this process owns and, on rank 0, writes the outputs. Bad input throws
// InputError; a realisation that fails throws on every rank.
RunStatus runEnsemble(const EnsembleRequest& request);

}  // namespace vf

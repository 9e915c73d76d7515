// What `voxfall ensemble` writes besides the rasters (README, "Ensembles and hazard maps"):
// runs.csv, paths.csv, converge.csv and summary.json. Coordinates are the DEM file's own (the
// scene's offset undone). Nothing written depends on threads, ranks or the clock.
#pragma once

#include <cstdint>
#include <cstdio>
#include <optional>
#include <vector>

#include "render/run/ensemble_files.h"
#include "sim/ensemble/ensemble.h"
#include "sim/ensemble/ensemble_stats.h"
#include "sim/scene/scene.h"

namespace vf {

// One row per realisation: index, seed, shape, release x/y/z, stop x/y/z and time, runout (m),
// reach angle (deg), max speed (m/s), max energy (kJ), max jump height (m), state, steps,
// checksum (16 hex digits).
void writeRunsCsv(std::FILE* out, const Ensemble& ensemble,
                  const std::vector<RealisationResult>& runs);
// index,time,x,y,z: every realisation's centre of mass after every step, in their shortest exact
// text (number_text.h).
void writePathsCsv(std::FILE* out, const Heightfield& dem,
                   const std::vector<RealisationResult>& runs);
// converge.csv (runs, cell i and j, cell centre x and y, passages, reach probability, p95
// energy in kJ), and the same as a table on `table` (stderr).
void writeConvergence(std::FILE* out, std::FILE* table, const Heightfield& dem,
                      const std::vector<ConvergenceRow>& rows);
// summary.json: scene, seed, runs, whether the run was interrupted (and which realisations the
// files hold then), states, runout and reach-angle distributions, the DEM, each statistic
// (name, title, units, maximum, files), the definitions, and the convergence rows when there
// are any.
void writeEnsembleSummary(std::FILE* out, const SceneSpec& spec, const Heightfield& dem,
                          const EnsembleRunInfo& info, const std::vector<RealisationResult>& runs,
                          const std::vector<StatLayer>& layers,
                          const std::vector<ConvergenceRow>& convergence);

}  // namespace vf

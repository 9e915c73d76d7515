// What a run of the voxfall command reports, shared by `simulate`, `render` and `export` so all
// report the same numbers the same way: the per-frame CSV, the summary JSON and the human
// summary (what a run reads is render/run/run_input.h; the progress line is render/progress.h).
#pragma once

#include <cstdio>
#include <string>
#include <vector>

#include "sim/recorder.h"
#include "sim/world.h"

namespace vf {

// voxfall's version, as `voxfall --version` prints it (after "voxfall ") and journals record it.
const char* voxfallVersion();

// Per-frame trajectory CSV: one row per ACTIVE body per frame, position = centre of mass (m),
// q = orientation (w, x, y, z), v (m/s) and w (rad/s, world frame), each number in its shortest
// text that reads back bit-exact (render/output/number_text.h).
void writeCsvHeader(std::FILE* out);
// `states` and `active` are the frame's states and released flags (Recorder::frameStates(),
// frameActive()), one per body of `world`.
void writeCsvFrame(std::FILE* out, int frame, double time, const World& world,
                   const std::vector<BodyState>& states, const std::vector<char>& active);

// How a run was stopped early by a signal: the signal (0: it was not) and the time of the last
// complete frame, s.
struct RunInterruption {
  int signal = 0;
  double time = 0;
};

// The run summary as one JSON object (keys: scene, frames, steps, dt_min, dt_max,
// wall_seconds, sphere_tests, contacts, max_penetration_body_body, max_penetration_body_ground,
// tunnelled, kinetic_energy, potential_energy, checksum, warnings {overlapping_releases,
// frozen_non_finite, floored_steps}, interrupted: null or {signal, time, frames}). Non-finite
// numbers become null.
void writeSummaryJson(std::FILE* out, const std::string& scene, const RunSummary& summary,
                      const RunInterruption& interruption = {});
// A few human-readable lines with the same numbers, ending with the checksum.
void printSummary(std::FILE* out, const std::string& scene, const RunSummary& summary);

}  // namespace vf

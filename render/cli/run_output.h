// What a run of the voxfall command writes, shared by `simulate` and `render` so both report the
// same numbers the same way: the per-frame CSV, the summary JSON, the human summary, the
// progress line, and the output rules of a run (files go through render/output/output_file.h).
#pragma once

#include <chrono>
#include <cstdio>
#include <optional>
#include <string>
#include <vector>

#include "render/output/output_file.h"
#include "sim/bake.h"
#include "sim/recorder.h"
#include "sim/scene/scene.h"
#include "sim/world.h"

namespace vf::cli {

// Per-frame trajectory CSV: one row per ACTIVE body per frame, position = centre of mass (m),
// q = orientation (w, x, y, z), v (m/s) and w (rad/s, world frame), numbers in %.17g so that
// they read back bit-exact.
void writeCsvHeader(std::FILE* out);
// `states` are the frame's states (Recorder::frameStates()), one per body of `world`.
void writeCsvFrame(std::FILE* out, int frame, double time, const World& world,
                   const std::vector<BodyState>& states);

// The run summary as one JSON object (keys: scene, frames, steps, dt_min, dt_max,
// wall_seconds, sphere_tests, contacts, max_penetration_body_body, max_penetration_body_ground,
// tunnelled, kinetic_energy, potential_energy, checksum, warnings {overlapping_releases,
// frozen_non_finite, floored_steps}). Non-finite numbers become null.
void writeSummaryJson(std::FILE* out, const std::string& scene, const RunSummary& summary);
// A few human-readable lines with the same numbers, ending with the checksum.
void printSummary(std::FILE* out, const std::string& scene, const RunSummary& summary);

// One progress line on stderr for runs longer than a second: redrawn in place ("\r") when
// stderr is a terminal, else a plain line every few seconds (logs, CI). Disabled: silent.
class Progress {
 public:
  Progress(std::string label, int totalFrames, bool enabled);
  ~Progress();  // finish()
  // Frames done so far (1..total) and the simulated time reached, s.
  void update(int framesDone, double simTime);
  // Frames done so far (1..total) and what to say about the latest one, e.g. "frame 30,
  // 8.40 frames/s". The line adds the share done, the time elapsed and the time left.
  void update(int framesDone, const std::string& detail);
  // Clears the in-place line, if one was drawn.
  void finish();

 private:
  using Clock = std::chrono::steady_clock;
  std::string label_;
  int total_;
  bool enabled_;
  bool tty_;
  bool drawn_ = false;
  Clock::time_point start_;
  Clock::time_point lastDraw_;
};

// What a run reads: a scene file, or a bake (sim/bake.h) recognised by its first line. The
// --level and --step overrides apply to a scene; for a bake, whose steps are recorded, they
// are an error.
struct RunInput {
  SceneSpec spec;            // the scene, or the bake's scene data
  std::optional<Bake> bake;  // set when the input is a bake
};
RunInput loadRunInput(const std::string& path, std::optional<int> level, const std::string& step);

// The output rules of a run (-y, -n) protecting every file it reads: the scene (or bake),
// each shape's mesh, and the terrain.
OutputRules runOutputRules(const SceneSpec& spec, const std::string& inputFile, bool overwrite,
                           bool neverOverwrite);

}  // namespace vf::cli

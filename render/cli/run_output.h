// What a run of the voxfall command writes, shared by `simulate` and `render` so both report the
// same numbers the same way: output files that appear only when complete, the per-frame CSV,
// the summary JSON, the human summary, the progress line, and Ctrl-C handling.
#pragma once

#include <chrono>
#include <cstdio>
#include <string>

#include "sim/recorder.h"
#include "sim/scene/scene.h"
#include "sim/world.h"

namespace vf::cli {

// An output file written under a temporary name in the destination folder and renamed over
// `path` by commit() only: a failed or interrupted run never leaves a half-written file in place
// of a good one. The constructor creates the temporary file, so an unwritable destination is
// reported (InputError naming `path`) before any simulation starts. The temporary name keeps
// the extension (".NAME.partial-PID-N.EXT") for writers that choose a format by it.
// SIGINT and SIGTERM remove every pending temporary file, then end the process as the signal
// would (even in the middle of a long frame), so Ctrl-C leaves nothing behind either. The
// handlers are installed when the first OutputFile is created; a command that wants a graceful
// stop instead (finishing a playable video) should install its own handlers after that, and
// restore them when done: OutputFile's destructor still removes uncommitted files.
class OutputFile {
 public:
  explicit OutputFile(const std::string& path);
  ~OutputFile();  // removes the temporary file unless committed
  OutputFile(const OutputFile&) = delete;
  OutputFile& operator=(const OutputFile&) = delete;

  const std::string& path() const { return path_; }
  const std::string& tempPath() const { return tempPath_; }
  // The open temporary file; null after closeStream() or commit().
  std::FILE* stream() { return file_; }
  // Closes the stream for writers that reopen tempPath() by name (e.g. a video muxer).
  void closeStream();
  // Flushes, closes and renames onto path(). Throws InputError on any I/O failure.
  void commit();

 private:
  std::string path_;
  std::string tempPath_;
  std::FILE* file_ = nullptr;
  bool committed_ = false;
};

// Per-frame trajectory CSV: one row per ACTIVE body per frame, position = centre of mass (m),
// q = orientation (w, x, y, z), v (m/s) and w (rad/s, world frame), numbers in %.17g so that
// they read back bit-exact.
void writeCsvHeader(std::FILE* out);
void writeCsvFrame(std::FILE* out, int frame, double time, const World& world);

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

// Command-line overrides shared by the commands, so `simulate` and `render` given the same
// options build the same world and report the same checksum.
// --level N: every shape uses level N (per-shape levels in the scene are overridden too).
void applyLevelOverride(SceneSpec& spec, int level);
// --step S|auto: "" when `text` is "auto" or a step in seconds > 0 ("0.005" or "1/120"),
// else what is wrong.
std::string checkStepOption(const std::string& text);
// Applies a --step value that passed checkStepOption.
void applyStepOverride(SceneSpec& spec, const std::string& text);
// --size WxH: "" when `text` is a frame size of 16..8192 pixels a side, else what is wrong.
std::string checkSize(const std::string& text);
// --collider voxel|polygon: the contact method of every body.
void applyColliderOverride(SceneSpec& spec, const std::string& method);

}  // namespace vf::cli

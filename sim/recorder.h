// Drives a World through the output frames of a run: frame k is the state at exactly
// t = k / fps (k = 0 .. floor(duration * fps)). At every frame it measures the true-mesh
// diagnostics and folds the state hash into the trajectory checksum. The simulation and the
// renderer both read frames through it, so `simulate` and `render` report the same checksum.
#pragma once

#include <cstdint>
#include <string>

#include "sim/world.h"

namespace vf {

struct RunSummary {
  int frames = 0;                       // output frames visited
  RunStats totals;                      // steps, dt range, sphere tests, contacts
  double wallSeconds = 0;               // time spent stepping and measuring
  double maxPenetrationBodyBody = 0;    // m, max over frames
  double maxPenetrationBodyGround = 0;  // m, max over frames
  int tunnelled = 0;                    // max over frames
  double kineticEnergy = 0;             // J, at the last frame
  double potentialEnergy = 0;           // J, at the last frame
  std::uint64_t checksum = 0;           // hash of the state hashes of every visited frame
  std::string checksumHex() const;      // 16 lowercase hex digits
};

class Recorder {
 public:
  Recorder(World& world, double fps, double duration);

  // Frames k = 0 .. floor(duration * fps) (the 1e-9 absorbs duration * fps landing a hair
  // below an integer); known before any world exists.
  static int frameCountFor(double fps, double duration);
  int frameCount() const { return frameCount_; }
  double frameTime(int k) const { return static_cast<double>(k) / fps_; }
  // Advances the world to frame k (k must not go backwards) and records it.
  void advanceToFrame(int k);
  const RunSummary& summary() const { return summary_; }
  const Diagnostics& lastDiagnostics() const { return last_; }
  World& world() { return world_; }

 private:
  World& world_;
  double fps_;
  int frameCount_;
  int nextFrame_ = 0;
  RunSummary summary_;
  Diagnostics last_;
  std::uint64_t hashState_;
};

}  // namespace vf

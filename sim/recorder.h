// Reads a World at the output frames of a run: frame k is the state at exactly t = k / fps
// (k = 0 .. floor(duration * fps)). The world takes its own steps (World::advanceTo never
// shortens a step to meet a frame), and the frame is a copy of the last step's state moved by
// free motion to t (World::statesAt), so the frame rate never changes the physics. At every
// frame it measures the true-mesh diagnostics; the checksum is the world's hash over its
// steps up to the scene's duration, the same at every fps. The simulation and the renderer
// both read frames through it, so `simulate` and `render` report the same checksum.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "sim/world.h"

namespace vf {

struct RunSummary {
  int frames = 0;                       // output frames visited
  RunStats totals;                      // steps, dt range, sphere tests, contacts
  double wallSeconds = 0;               // time spent stepping and measuring
  double diagnosticsSeconds = 0;        // of which measuring (World::measure at every frame)
  double maxPenetrationBodyBody = 0;    // m, max over frames
  double maxPenetrationBodyGround = 0;  // m, max over frames
  int tunnelled = 0;                    // max over frames
  double kineticEnergy = 0;             // J, after the run's last step (see advanceToFrame)
  double potentialEnergy = 0;           // J, after the run's last step
  std::uint64_t checksum = 0;           // World::stepsHash() over the steps of the run
  std::string checksumHex() const;      // 16 lowercase hex digits
};

// A trajectory checksum as 16 lowercase hex digits, as `simulate` prints it and runs.csv holds it.
std::string checksumHex(std::uint64_t checksum);

class Recorder {
 public:
  Recorder(World& world, double fps, double duration);

  // Frames k = 0 .. floor(duration * fps / speed) (the 1e-9 absorbs the product landing a hair
  // below an integer); known before any world exists. `speed`: simulated seconds per second of
  // video ([output] speed; the renderer's frames), 1 for the simulation's own frames.
  static int frameCountFor(double fps, double duration, double speed = 1);
  // The time of frame k at `speed`: (k speed) / fps, s. k speed is exact for whole speeds and
  // powers of two, so frame k at speed 2 is frame 2k at speed 1 to the bit; speed 1 gives
  // frameTime(k).
  static double frameTimeFor(int k, double fps, double speed = 1) {
    return (static_cast<double>(k) * speed) / fps;
  }
  int frameCount() const { return frameCount_; }
  double frameTime(int k) const { return static_cast<double>(k) / fps_; }
  // Advances the world through its steps up to frame k's time (k must not go backwards) and
  // records frame k. The last frame also takes the steps up to the duration, so the summary's
  // step count and checksum do not depend on fps.
  void advanceToFrame(int k);
  // Every body's state at the last recorded frame (body id order), see World::statesAt.
  const std::vector<BodyState>& frameStates() const { return frame_; }
  const RunSummary& summary() const { return summary_; }
  const Diagnostics& lastDiagnostics() const { return last_; }
  // Called after every step the recorder makes the world take (e.g. to record a bake).
  void setAfterStep(std::function<void()> afterStep) { afterStep_ = std::move(afterStep); }
  World& world() { return world_; }

 private:
  World& world_;
  double fps_;
  double duration_;
  int frameCount_;
  int nextFrame_ = 0;
  RunSummary summary_;
  Diagnostics last_;
  std::vector<BodyState> frame_;
  std::function<void()> afterStep_;
};

}  // namespace vf

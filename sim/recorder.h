// Reads a World at the output frames of a run: frame k is the state at t = k / fps
// (k = 0 .. floor(duration * fps)). The world takes its own steps (never shortened to meet a
// frame), and the frame is taken from the two step states that bracket t (sim/frame_interp.h),
// so the frame rate never changes the physics and a body at rest between two steps is at rest in
// the frame. For that the recorder runs the world one step past the frame time, keeping the
// state before that step: one extra copy of the body states. It never steps past the duration,
// nor past a frame after which the run ends (setRunEnds): a frame after the run's last step
// holds that step's state. At every frame it measures the true-mesh diagnostics; the checksum
// is the world's hash over its steps up to the scene's duration, the same at every fps. The
// simulation and the renderer both read frames through it, so `simulate` and `render` report
// the same checksum.
#pragma once

#include <cstdint>
#include <deque>
#include <functional>
#include <string>
#include <vector>

#include "sim/frame_interp.h"
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
  // Every body's state at the last recorded frame (body id order), and its released flags.
  const std::vector<BodyState>& frameStates() const { return frame_; }
  const std::vector<char>& frameActive() const { return frameActive_; }
  // Every body's state at t (no earlier than the last frame or time asked for), sampled as a
  // frame is but neither measured nor counted: frames drawn between the recorder's frames.
  std::vector<BodyState> statesAt(double t, std::vector<char>& active);
  // Whether `runEnds` held after the last step at or before the last recorded frame.
  bool runEnded() const { return !kept_.empty() && kept_.front().ends; }
  const RunSummary& summary() const { return summary_; }
  const Diagnostics& lastDiagnostics() const { return last_; }
  // Called after every step the recorder makes the world take (e.g. to record a bake).
  void setAfterStep(std::function<void()> afterStep) { afterStep_ = std::move(afterStep); }
  // A run that may end early (`voxfall simulate`: a rock at a "stop" edge, every rock at
  // rest) ends after the first frame whose last step satisfies `runEnds`, asked after each
  // step. The world is not stepped past a frame time from such a step, so the run takes the
  // steps it would take if frames were read without looking ahead (runEnded()).
  void setRunEnds(std::function<bool()> runEnds);
  World& world() { return world_; }

 private:
  // A step state kept for sampling, with what the run's summary and runEnds said after it.
  struct Kept {
    StepState step;
    std::uint64_t checksum = 0;
    RunStats totals;
    bool ends = false;
  };
  // Takes the world's steps a sample at t needs: those ending at or before t, then the one
  // crossing t unless the run ends before it; keeps the step states from the last at or
  // before t on.
  void stepFor(double t);
  void takeStep(double t);
  void keep();
  std::vector<BodyState> sample(double t, std::vector<char>& active);

  World& world_;
  double fps_;
  double duration_;
  int frameCount_;
  int nextFrame_ = 0;
  RunSummary summary_;
  Diagnostics last_;
  std::vector<BodyState> frame_;
  std::vector<char> frameActive_;
  double sampled_ = 0;     // the latest time sampled, s
  std::deque<Kept> kept_;  // step states from the last at or before sampled_ on (2 or 3)
  std::function<void()> afterStep_;
  std::function<bool()> runEnds_;
};

}  // namespace vf

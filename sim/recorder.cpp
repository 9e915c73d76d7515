#include "sim/recorder.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>

#include "sim/core/error.h"

namespace vf {

std::string checksumHex(std::uint64_t checksum) {
  char buf[17];
  std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(checksum));
  return buf;
}

std::string RunSummary::checksumHex() const { return vf::checksumHex(checksum); }

int Recorder::frameCountFor(double fps, double duration, double speed) {
  return static_cast<int>(std::floor(duration * fps / speed + 1e-9)) + 1;
}

Recorder::Recorder(World& world, double fps, double duration)
    : world_(world), fps_(fps), duration_(duration), frameCount_(frameCountFor(fps, duration)) {
  VF_ASSERT(fps > 0 && duration >= 0);
}

void Recorder::advanceToFrame(int k) {
  VF_ASSERT(k >= nextFrame_ && k < frameCount_);
  const auto start = std::chrono::steady_clock::now();
  // World::measure, timed (the diagnostics' share of a run).
  auto measure = [this](const std::vector<BodyState>* states) {
    const auto begin = std::chrono::steady_clock::now();
    const Diagnostics d = states ? world_.measure(*states) : world_.measure();
    summary_.diagnosticsSeconds +=
        std::chrono::duration<double>(std::chrono::steady_clock::now() - begin).count();
    return d;
  };
  // Frames skipped over are still measured: the diagnostics cover every frame up to k, so a
  // partial render (--frames A:B) and a full run agree on their common prefix.
  for (int f = nextFrame_; f <= k; ++f) {
    const double t = frameTime(f);
    world_.advanceTo(t, afterStep_);
    frame_ = world_.statesAt(t);
    last_ = measure(&frame_);
    summary_.maxPenetrationBodyBody =
        std::max(summary_.maxPenetrationBodyBody, last_.maxPenetrationBodyBody);
    summary_.maxPenetrationBodyGround =
        std::max(summary_.maxPenetrationBodyGround, last_.maxPenetrationBodyGround);
    summary_.tunnelled = std::max(summary_.tunnelled, last_.tunnelled);
  }
  // The run's steps end at the duration whatever the frame rate (the last frame time
  // floor(duration * fps) / fps depends on fps).
  // The final energies are the last step's (a simulated state, the same at every fps), not
  // the last frame's, whose free motion adds gravity's increment to bodies at rest.
  Diagnostics end = last_;
  if (k == frameCount_ - 1) {
    world_.advanceTo(std::max(duration_, frameTime(k)), afterStep_);
    end = measure(nullptr);
  }
  nextFrame_ = k + 1;
  summary_.frames = nextFrame_;
  summary_.totals = world_.totals();
  summary_.kineticEnergy = end.kineticEnergy;
  summary_.potentialEnergy = end.potentialEnergy;
  summary_.checksum = world_.stepsHash();
  summary_.wallSeconds +=
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace vf

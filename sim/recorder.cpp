#include "sim/recorder.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>

#include "sim/core/error.h"
#include "sim/core/hash.h"

namespace vf {

std::string RunSummary::checksumHex() const {
  char buf[17];
  std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(checksum));
  return buf;
}

int Recorder::frameCountFor(double fps, double duration) {
  return static_cast<int>(std::floor(duration * fps + 1e-9)) + 1;
}

Recorder::Recorder(World& world, double fps, double duration)
    : world_(world),
      fps_(fps),
      frameCount_(frameCountFor(fps, duration)),
      hashState_(Hasher().value()) {
  VF_ASSERT(fps > 0 && duration >= 0);
}

void Recorder::advanceToFrame(int k) {
  VF_ASSERT(k >= nextFrame_ && k < frameCount_);
  const auto start = std::chrono::steady_clock::now();
  // Frames skipped over still count in the checksum: it covers every frame up to k, so a
  // partial render (--frames A:B) and a full run agree on their common prefix.
  for (int f = nextFrame_; f <= k; ++f) {
    world_.advanceTo(frameTime(f));
    last_ = world_.measure();
    summary_.maxPenetrationBodyBody =
        std::max(summary_.maxPenetrationBodyBody, last_.maxPenetrationBodyBody);
    summary_.maxPenetrationBodyGround =
        std::max(summary_.maxPenetrationBodyGround, last_.maxPenetrationBodyGround);
    summary_.tunnelled = std::max(summary_.tunnelled, last_.tunnelled);
    Hasher h;
    h.add(hashState_);
    h.add(world_.stateHash());
    hashState_ = h.value();
  }
  nextFrame_ = k + 1;
  summary_.frames = nextFrame_;
  summary_.totals = world_.totals();
  summary_.kineticEnergy = last_.kineticEnergy;
  summary_.potentialEnergy = last_.potentialEnergy;
  summary_.checksum = hashState_;
  summary_.wallSeconds +=
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace vf

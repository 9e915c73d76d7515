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
  keep();
}

void Recorder::setRunEnds(std::function<bool()> runEnds) {
  runEnds_ = std::move(runEnds);
  kept_.back().ends = runEnds_ && runEnds_();  // the world is at its last kept state
}

void Recorder::keep() {
  Kept k;
  k.step.time = world_.time();
  k.step.states.reserve(static_cast<std::size_t>(world_.bodyCount()));
  k.step.active.reserve(static_cast<std::size_t>(world_.bodyCount()));
  for (int id = 0; id < world_.bodyCount(); ++id) {
    k.step.states.push_back(world_.state(id));
    k.step.active.push_back(world_.isActive(id) ? 1 : 0);
  }
  k.checksum = world_.stepsHash();
  k.totals = world_.totals();
  k.ends = runEnds_ && runEnds_();
  kept_.push_back(std::move(k));
}

void Recorder::takeStep(double t) {
  world_.stepNext();  // throws RunawayError when the run guard stopped the run
  if (afterStep_) afterStep_();
  // A step followed by another that still ends by t is never sampled (samples come in time
  // order): not kept, so several steps per frame cost no copies.
  if (world_.nextStepEnd() > t + kTimeTolerance) keep();
}

void Recorder::stepFor(double t) {
  VF_ASSERT(t >= sampled_ - kTimeTolerance);
  sampled_ = std::max(sampled_, t);
  // The steps ending by t, as World::advanceTo takes them.
  while (world_.nextStepEnd() <= t + kTimeTolerance) takeStep(t);
  VF_ASSERT(kept_.back().step.time == world_.time());
  // The step crossing t, unless the run ends first: at the duration, or after this frame
  // (runEnds on the last step at or before t, the state the run's end is decided on).
  if (world_.time() < t - kTimeTolerance && !kept_.back().ends &&
      world_.nextStepEnd() <= duration_ + kTimeTolerance) {
    try {
      takeStep(t);
    } catch (const RunawayError&) {
      // The run stops at the step before; frames up to the next step needed hold that state
      // and the next frame that needs a step throws, as without looking ahead.
    }
  }
  while (kept_.size() > 1 && kept_[1].step.time <= t + kTimeTolerance) kept_.pop_front();
}

std::vector<BodyState> Recorder::sample(double t, std::vector<char>& active) {
  stepFor(t);
  return sampleSteps(kept_.front().step, kept_.size() > 1 ? &kept_[1].step : nullptr, t, active);
}

std::vector<BodyState> Recorder::statesAt(double t, std::vector<char>& active) {
  return sample(t, active);
}

void Recorder::advanceToFrame(int k) {
  VF_ASSERT(k >= nextFrame_ && k < frameCount_);
  const auto start = std::chrono::steady_clock::now();
  // World::measure, timed (the diagnostics' share of a run).
  auto measure = [this](const std::vector<BodyState>* states) {
    const auto begin = std::chrono::steady_clock::now();
    const Diagnostics d = states ? world_.measure(*states, frameActive_) : world_.measure();
    summary_.diagnosticsSeconds +=
        std::chrono::duration<double>(std::chrono::steady_clock::now() - begin).count();
    return d;
  };
  // Frames skipped over are still measured: the diagnostics cover every frame up to k, so a
  // partial render (--frames A:B) and a full run agree on their common prefix.
  for (int f = nextFrame_; f <= k; ++f) {
    frame_ = sample(frameTime(f), frameActive_);
    last_ = measure(&frame_);
    summary_.maxPenetrationBodyBody =
        std::max(summary_.maxPenetrationBodyBody, last_.maxPenetrationBodyBody);
    summary_.maxPenetrationBodyGround =
        std::max(summary_.maxPenetrationBodyGround, last_.maxPenetrationBodyGround);
    summary_.tunnelled = std::max(summary_.tunnelled, last_.tunnelled);
  }
  // Steps, checksum and energies are those of the steps up to the frame (the last kept at or
  // before it), not of the step the recorder took past it.
  summary_.totals = kept_.front().totals;
  summary_.checksum = kept_.front().checksum;
  Diagnostics end = last_;
  // The run's steps end at the duration whatever the frame rate (the last frame time
  // floor(duration * fps) / fps depends on fps). Those past the last frame are kept, for frames
  // drawn after it (statesAt). The final energies are the last step's (a simulated state, the
  // same at every fps), not the last frame's.
  if (k == frameCount_ - 1) {
    while (world_.nextStepEnd() <= std::max(duration_, frameTime(k)) + kTimeTolerance)
      takeStep(sampled_);
    end = measure(nullptr);
    summary_.totals = world_.totals();
    summary_.checksum = world_.stepsHash();
  }
  nextFrame_ = k + 1;
  summary_.frames = nextFrame_;
  summary_.kineticEnergy = end.kineticEnergy;
  summary_.potentialEnergy = end.potentialEnergy;
  summary_.wallSeconds +=
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace vf

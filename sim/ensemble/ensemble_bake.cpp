// A subset of an ensemble as a bake (see ensemble_bake.h). Each realisation is stepped again in
// its own world, frame by frame, exactly as Ensemble::run steps it (same seed, same step
// sequence, same end), so the bake shows the trajectories the statistics were made from. A frame
// is sampled from the two steps that bracket it (frame_interp.h), as the recorder samples one.
#include "sim/ensemble/ensemble_bake.h"

#include <algorithm>

#include "sim/core/error.h"
#include "sim/frame_interp.h"
#include "sim/recorder.h"

namespace vf {

Bake ensembleBake(const Ensemble& ensemble, std::uint64_t ensembleSeed,
                  const std::vector<std::int64_t>& indices, std::vector<std::uint64_t>* checksums) {
  const SceneSpec& spec = ensemble.spec();
  Bake bake;
  bake.scene = spec;
  bake.scene.bodies.clear();
  bake.scene.emitters.clear();
  bake.scene.ensemble.reset();
  const int frames = Recorder::frameCountFor(spec.fps, spec.duration);
  bake.records.resize(static_cast<std::size_t>(frames));
  for (int k = 0; k < frames; ++k) bake.records[static_cast<std::size_t>(k)].time = k / spec.fps;

  int lastFrame = indices.empty() ? frames - 1 : 0;
  for (std::size_t b = 0; b < indices.size(); ++b) {
    int shapeIndex = 0;
    const std::unique_ptr<World> world =
        ensemble.makeWorld(realisationSeed(ensembleSeed, indices[b]), &shapeIndex);
    World& w = *world;
    const std::string& shapeName = ensemble.ensemble().shapes[static_cast<std::size_t>(shapeIndex)];
    const auto shape = std::find_if(spec.shapes.begin(), spec.shapes.end(),
                                    [&](const ShapeSpec& s) { return s.name == shapeName; });
    VF_ASSERT(shape != spec.shapes.end());
    BakeBody body;
    body.shape = static_cast<int>(shape - spec.shapes.begin());
    body.color = defaultBodyColor(static_cast<int>(b));
    body.invMass = 1.0 / w.shape(0).mass;
    body.inertiaBodyInv = w.shape(0).inertiaBodyInv;
    bake.bodies.push_back(body);

    // Released flag of the rock: off once it left the DEM or was buried.
    auto present = [&w] {
      const RockState s = w.outcomes()[0].state;
      return static_cast<char>(s == RockState::kLeft || s == RockState::kBuried ? 0 : 1);
    };
    // The state after the last step taken and the one before it (frame_interp.h).
    StepState now{w.time(), {w.state(0)}, {present()}}, before = now;
    bool ended = false;
    int endFrame = frames - 1;  // the first frame at which the realisation has ended
    // Ensemble::run's loop: steps of the scene's own sequence, ending when the rock does or at
    // the duration; a frame may take the next of them early, never one Ensemble::run does not.
    auto step = [&] {
      w.stepNext();
      ended = w.outcomes()[0].state != RockState::kMoving;
      before = std::move(now);
      now = StepState{w.time(), {w.state(0)}, {present()}};
    };
    auto mayStep = [&] { return !ended && w.nextStepEnd() <= spec.duration + kTimeTolerance; };
    for (int k = 0; k < frames; ++k) {
      const double t = bake.records[static_cast<std::size_t>(k)].time;
      while (mayStep() && w.nextStepEnd() <= t + kTimeTolerance) step();
      if (now.time < t - kTimeTolerance && mayStep()) step();  // the step crossing t
      if (ended && endFrame == frames - 1 && now.time <= t + kTimeTolerance) endFrame = k;
      std::vector<char> active;
      const bool between = now.time > t + kTimeTolerance;
      const BodyState y =
          sampleSteps(between ? before : now, between ? &now : nullptr, t, active)[0];
      BakeRecord& r = bake.records[static_cast<std::size_t>(k)];
      r.states.push_back(y);
      r.active.push_back(active[0]);
    }
    lastFrame = std::max(lastFrame, endFrame);
    if (checksums) {
      // A realisation still moving at the last frame time takes Ensemble::run's remaining
      // steps up to the duration (none when the duration is a whole number of frames), so the
      // checksum covers the same steps as its row in runs.csv.
      while (!ended && w.nextStepEnd() <= spec.duration + kTimeTolerance) {
        w.stepNext();
        ended = w.outcomes()[0].state != RockState::kMoving;
      }
      checksums->push_back(w.stepsHash());
    }
  }
  // Nothing changes after the frame at which the last realisation has ended: the bake stops
  // there (rocks that stop early would otherwise hold still to the scene's duration, in a
  // video of that length), and its scene's duration with it, which is what `voxfall render`
  // counts the frames by (Recorder::frameCountFor gives lastFrame + 1 for lastFrame / fps).
  if (lastFrame + 1 < frames) {
    bake.records.resize(static_cast<std::size_t>(lastFrame + 1));
    bake.scene.duration = bake.records.back().time;
  }
  return bake;
}

}  // namespace vf

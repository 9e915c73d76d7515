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

namespace {

// The bake's scene (the ensemble's, without its bodies) and its frame times, with no body yet.
Bake emptyBake(const SceneSpec& spec, int frames) {
  Bake bake;
  bake.scene = spec;
  bake.scene.bodies.clear();
  bake.scene.emitters.clear();
  bake.scene.ensemble.reset();
  bake.records.resize(static_cast<std::size_t>(frames));
  for (int k = 0; k < frames; ++k) bake.records[static_cast<std::size_t>(k)].time = k / spec.fps;
  return bake;
}

// The rock of a realisation's world (its body 0) as the bake's body b, with the shape drawn.
BakeBody bakeBody(const Ensemble& ensemble, const World& w, int shapeIndex, std::size_t b) {
  const SceneSpec& spec = ensemble.spec();
  const std::string& shapeName = ensemble.ensemble().shapes[static_cast<std::size_t>(shapeIndex)];
  const auto shape = std::find_if(spec.shapes.begin(), spec.shapes.end(),
                                  [&](const ShapeSpec& s) { return s.name == shapeName; });
  VF_ASSERT(shape != spec.shapes.end());
  BakeBody body;
  body.shape = static_cast<int>(shape - spec.shapes.begin());
  body.color = defaultBodyColor(static_cast<int>(b));
  body.invMass = 1.0 / w.shape(0).mass;
  body.inertiaBodyInv = w.shape(0).inertiaBodyInv;
  return body;
}

// A realisation's world stepped as Ensemble::run steps it: steps of the scene's own sequence,
// ending when the rock does or at the duration. Keeps the state after the last step taken and
// the one before it (frame_interp.h).
class Realisation {
 public:
  Realisation(World& w, const RockFall& rockFall, double duration)
      : w_(w),
        rockFall_(rockFall),
        duration_(duration),
        now_{w.time(), {w.state(0)}, {present()}},
        before_(now_) {}

  bool ended() const { return ended_; }
  const StepState& now() const { return now_; }
  const StepState& before() const { return before_; }
  double nextStepEnd() const { return w_.nextStepEnd(); }
  // Whether Ensemble::run takes another step.
  bool mayStep() const { return !ended_ && w_.nextStepEnd() <= duration_ + kTimeTolerance; }
  void step() {
    w_.stepNext();
    ended_ = rockFall_.outcomes()[0].state != RockState::kMoving;
    before_ = std::move(now_);
    now_ = StepState{w_.time(), {w_.state(0)}, {present()}};
  }

 private:
  // Released flag of the rock: off once it left the DEM or was buried.
  char present() const {
    const RockState s = rockFall_.outcomes()[0].state;
    return static_cast<char>(s == RockState::kLeft || s == RockState::kBuried ? 0 : 1);
  }

  World& w_;
  const RockFall& rockFall_;
  double duration_;
  bool ended_ = false;
  StepState now_, before_;
};

// Appends the realisation's rock to every frame of the bake, stepping it as far as the frames
// need (a frame may take the next step early, never one Ensemble::run does not). Returns the
// first frame at which the realisation has ended (the last frame if it has not).
int recordFrames(Realisation& rock, Bake& bake) {
  const int frames = static_cast<int>(bake.records.size());
  int endFrame = frames - 1;
  for (int k = 0; k < frames; ++k) {
    BakeRecord& r = bake.records[static_cast<std::size_t>(k)];
    const double t = r.time;
    while (rock.mayStep() && rock.nextStepEnd() <= t + kTimeTolerance) rock.step();
    if (rock.now().time < t - kTimeTolerance && rock.mayStep()) rock.step();  // crossing t
    if (rock.ended() && endFrame == frames - 1 && rock.now().time <= t + kTimeTolerance)
      endFrame = k;
    std::vector<char> active;
    const bool between = rock.now().time > t + kTimeTolerance;
    const BodyState y = sampleSteps(between ? rock.before() : rock.now(),
                                    between ? &rock.now() : nullptr, t, active)[0];
    r.states.push_back(y);
    r.active.push_back(active[0]);
  }
  return endFrame;
}

}  // namespace

Bake ensembleBake(const Ensemble& ensemble, std::uint64_t ensembleSeed,
                  const std::vector<std::int64_t>& indices, std::vector<std::uint64_t>* checksums) {
  const SceneSpec& spec = ensemble.spec();
  const int frames = Recorder::frameCountFor(spec.fps, spec.duration);
  Bake bake = emptyBake(spec, frames);
  int lastFrame = indices.empty() ? frames - 1 : 0;
  for (std::size_t b = 0; b < indices.size(); ++b) {
    const RealisationWorld made = ensemble.makeWorld(realisationSeed(ensembleSeed, indices[b]));
    bake.bodies.push_back(bakeBody(ensemble, *made.world, made.shape, b));
    Realisation rock(*made.world, *made.rockFall, spec.duration);
    lastFrame = std::max(lastFrame, recordFrames(rock, bake));
    if (checksums) {
      // A realisation still moving at the last frame time takes Ensemble::run's remaining
      // steps up to the duration (none when the duration is a whole number of frames), so the
      // checksum covers the same steps as its row in runs.csv.
      while (rock.mayStep()) rock.step();
      checksums->push_back(made.world->stepsHash());
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

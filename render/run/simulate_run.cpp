#include "render/run/simulate_run.h"

#include <cstdio>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "render/output/output_file.h"
#include "render/progress.h"
#include "render/run/lines_output.h"
#include "render/run/outcomes_output.h"
#include "render/run/run_input.h"
#include "render/run/run_report.h"
#include "sim/bake.h"
#include "sim/core/error.h"
#include "sim/ground/rock_fall.h"
#include "sim/recorder.h"
#include "sim/run_guard.h"
#include "sim/shape/sphere_tree.h"

namespace vf {
namespace {

// Every output of the run, checked and opened (each a temporary file until committed) before
// the expensive part.
struct SimulateOutputs {
  std::optional<OutputFile> csv, summary, bake, outcomes, barriers;
  std::optional<LineFiles> lines;
  std::string written;  // the paths committed, ", "-separated

  void wrote(OutputFile& f) {
    f.commit();
    note(f.path());
  }
  void note(const std::string& path) { written += (written.empty() ? "" : ", ") + path; }
};

// The paths of --csv, --summary and --bake, by option.
std::vector<std::pair<const char*, const std::string*>> namedPaths(const SimulateRequest& r) {
  return {{"--csv", &r.csv}, {"--summary", &r.summary}, {"--bake", &r.bake}};
}

// Two options naming one file would have the second rename clobber the first.
void checkDistinctPaths(const SimulateRequest& r) {
  const auto named = namedPaths(r);
  for (const auto& [a, pa] : named)
    for (const auto& [b, pb] : named)
      if (a < b && !pa->empty() && *pa == *pb)
        throw InputError("", std::string(a) + " and " + b + " name the same file '" + *pa + "'");
}

void checkOutcomesPath(const SimulateRequest& r) {
  for (const auto& [name, other] : namedPaths(r))
    if (r.outcomes == *other)
      throw InputError(
          "", std::string("--outcomes and ") + name + " name the same file '" + r.outcomes + "'");
}

void openOutputs(SimulateOutputs& out, const SimulateRequest& r, const SceneSpec& spec) {
  const OutputRules rules = runOutputRules(spec, r.scene, r.overwrite, r.neverOverwrite);
  checkDistinctPaths(r);
  if (!r.csv.empty()) out.csv.emplace(r.csv, rules);
  if (!r.summary.empty()) out.summary.emplace(r.summary, rules);
  if (!r.bake.empty()) out.bake.emplace(r.bake, rules);
  if (!r.outcomes.empty()) {
    checkOutcomesPath(r);
    if (spec.terrainPath.empty())
      throw InputError(spec.path, "--outcomes needs a scene with terrain ([ground] heightfield)");
    out.outcomes.emplace(r.outcomes, rules);
  }
  if (!r.lines.empty()) {
    if (spec.evaluationLines.empty())
      throw InputError(spec.path, "--lines needs [[evaluation_lines]] in the scene");
    out.lines.emplace(r.lines, rules, true);
  }
  if (!r.barriers.empty()) {
    if (spec.barriers.empty())
      throw InputError(spec.path, "--barriers needs [[barriers]] in the scene");
    out.barriers.emplace(r.barriers, rules);
  }
}

// The world being stepped and what records it besides the frames: the bake's steps and the
// evaluation lines' crossings (found on the world's steps, not on the frames:
// sim/ground/evaluation_lines.h).
struct Stepping {
  BuiltScene built;
  Recorder recorder;
  std::optional<Bake> bake;
  std::optional<CrossingRecorder> crossings;
  int done = 0;         // whole frames
  std::string runaway;  // set when the run guard stopped the run (sim/run_guard.h)

  Stepping(const SceneSpec& spec, const SimulateOutputs& out)
      : built(buildScene(spec)), recorder(*built.world, spec.fps, spec.duration) {
    if (out.bake) {
      bake = bakeHeader(spec, built);
      addBakeRecord(*bake, *built.world);  // t = 0, before the first step
    }
    // Decided on the last step at or before each frame (Recorder::setRunEnds).
    recorder.setRunEnds([this, settle = spec.stopWhenSettled] {
      const RockFall& rf = *built.rockFall;
      return !rf.stopReason().empty() || (settle && rf.allSettled(built.world->bodies()));
    });
    if (out.lines) {
      crossings.emplace(built.evaluationLines);
      crossings->observe(*built.world);
    }
    if (bake || crossings)
      recorder.setAfterStep([this] {
        if (bake) addBakeRecord(*bake, *built.world);
        if (crossings) crossings->observe(*built.world);
      });
  }
};

// Frame by frame; a stop signal ends the run after the frame in hand (stop_policy.h).
void stepFrames(Stepping& s, SimulateOutputs& out, const SceneSpec& spec, bool quiet) {
  Recorder& recorder = s.recorder;
  Progress progress(spec.name, recorder.frameCount(), !quiet);
  for (int k = 0; k < recorder.frameCount() && !stopRequested(); ++k) {
    try {
      recorder.advanceToFrame(k);
    } catch (const RunawayError& e) {
      // The frames so far are whole frames of a valid run up to the trouble: they are kept.
      s.runaway = e.what();
      break;
    }
    if (out.csv)
      writeCsvFrame(out.csv->stream(), k, recorder.frameTime(k), *s.built.world,
                    recorder.frameStates(), recorder.frameActive());
    s.done = k + 1;
    progress.update(s.done, recorder.frameTime(k));
    // Rock fall: the run ends when every rock has stopped or left (`stop = "all_at_rest"`),
    // or when a rock reached a terrain edge whose policy is "stop".
    if (recorder.runEnded()) break;
  }
  progress.finish();
}

// The rows and records of the complete frames are a valid run up to the trouble and are kept
// (a bake of them shows what went wrong); a summary or outcomes would pass for those of a
// finished run, so they are not written.
[[noreturn]] void keepRunawayFrames(Stepping& s, SimulateOutputs& out, const SimulateRequest& r,
                                    const SceneSpec& spec) {
  if (out.csv) out.csv->commit();
  if (out.bake && s.done > 0) {
    s.bake->scene.duration = s.recorder.frameTime(s.done - 1);
    writeBake(out.bake->stream(), r.bake, *s.bake);
    out.bake->commit();
  }
  throw InputError(spec.path, s.runaway);
}

void reportWorld(const World& world, const RockFall& rockFall) {
  for (const std::string& m : rockFall.terrainMessages())
    std::fprintf(stderr, "voxfall: warning: %s\n", m.c_str());
  if (!rockFall.stopReason().empty())
    std::fprintf(stderr, "voxfall: run stopped at t = %.4f s: %s\n", world.time(),
                 rockFall.stopReason().c_str());
}

void writeRockFiles(Stepping& s, SimulateOutputs& out, const SimulateRequest& r) {
  const World& world = *s.built.world;
  const RockFall& rockFall = *s.built.rockFall;
  if (out.outcomes) {
    if (r.outcomes.ends_with(".geojson") || r.outcomes.ends_with(".json"))
      writeOutcomesGeoJson(out.outcomes->stream(), world, rockFall);
    else
      writeOutcomesCsv(out.outcomes->stream(), world, rockFall);
    out.wrote(*out.outcomes);
  }
  if (out.lines) {
    std::int64_t rocks = 0;
    for (const RockOutcome& o : rockFall.outcomes()) rocks += o.released ? 1 : 0;
    out.lines->write(s.built.evaluationLines, s.crossings->crossings(), rocks,
                     world.def().terrain->shift);
    out.note(r.lines);
  }
  if (out.barriers) {
    std::vector<std::int64_t> failed;
    for (const BarrierResult& b : s.built.barriers->results()) failed.push_back(b.failed ? 1 : 0);
    writeBarriersCsv(out.barriers->stream(), s.built.barriers->barriers(),
                     s.built.barriers->results(), failed);
    out.wrote(*out.barriers);
  }
}

void writeRunFiles(Stepping& s, SimulateOutputs& out, const SimulateRequest& r,
                   const SceneSpec& spec, int stop) {
  const RunSummary& result = s.recorder.summary();
  if (out.summary) {
    // An interrupted run's summary says so, and up to which frame it holds.
    const RunInterruption cut{stop, stop ? s.recorder.frameTime(s.done - 1) : 0.0};
    writeSummaryJson(out.summary->stream(), spec.name, result, cut);
    out.wrote(*out.summary);
  }
  if (out.csv) out.wrote(*out.csv);
  if (out.bake) {
    s.bake->summary = result;
    // An interrupted (or settled, `stop = "all_at_rest"`) bake ends at its last frame, so it
    // renders only what was simulated.
    if (s.done < s.recorder.frameCount()) s.bake->scene.duration = s.recorder.frameTime(s.done - 1);
    writeBake(out.bake->stream(), r.bake, *s.bake);
    out.wrote(*out.bake);
  }
}

// The rocks' outcomes on terrain, in one line.
void printRocks(const World& world, const RockFall& rockFall, const SimulateRequest& r,
                bool outcomes, int stop) {
  int count[4] = {0, 0, 0, 0};
  for (const RockOutcome& o : rockFall.outcomes())
    if (o.released) ++count[static_cast<int>(o.state)];
  std::printf("  rocks: %d stopped, %d left the terrain, %d buried, %d still moving (t = %.3f s)\n",
              count[1], count[2], count[3], count[0], world.time());
  // The outcomes of rocks cut off by the duration are where they were then, which reads like a
  // runout unless told (an interrupted run says so when it ends instead).
  if (outcomes && count[0] > 0 && !stop)
    std::fprintf(stderr,
                 "voxfall: warning: %d of %d rocks were still moving at the end (t = %.4g s); "
                 "%s records them where they were then, not where they stop: raise "
                 "[simulation] duration\n",
                 count[0], count[0] + count[1] + count[2] + count[3], world.time(),
                 r.outcomes.c_str());
}

}  // namespace

RunStatus runSimulation(const SimulateRequest& r) {
  SceneSpec spec = loadScene(r.scene);
  applyOverrides(spec, r.overrides);
  SimulateOutputs out;
  openOutputs(out, r, spec);
  watchForStop();

  Stepping s(spec, out);
  if (out.csv) writeCsvHeader(out.csv->stream());
  stepFrames(s, out, spec, r.quiet);
  if (!s.runaway.empty()) keepRunawayFrames(s, out, r, spec);
  const int stop = stopRequested();
  // The OutputFiles' destructors remove their temporary files.
  if (stop && s.done == 0) return stoppedWithNothingWritten();
  reportWorld(*s.built.world, *s.built.rockFall);
  writeRockFiles(s, out, r);
  writeRunFiles(s, out, r, spec, stop);
  printSummary(stdout, spec.name, s.recorder.summary());
  if (!spec.terrainPath.empty())
    printRocks(*s.built.world, *s.built.rockFall, r, out.outcomes.has_value(), stop);
  if (stop)
    std::fprintf(stderr, "voxfall: interrupted; frames 0..%d (t = 0 .. %.6g s) written%s%s\n",
                 s.done - 1, s.recorder.frameTime(s.done - 1), out.written.empty() ? "" : " to ",
                 out.written.c_str());
  return stop ? RunStatus::stopped(stop) : RunStatus::done();
}

}  // namespace vf

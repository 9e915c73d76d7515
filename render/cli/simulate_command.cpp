// voxfall simulate SCENE: steps a scene through its output frames without drawing, writes the
// trajectory (CSV) and the run summary (JSON), and prints the summary and checksum.
//
// Order matters for the user: cheap checks first (scene file, then output paths), the expensive
// shape building and stepping last, so a typo never costs a long run.
#include <CLI/CLI.hpp>
#include <memory>
#include <optional>
#include <string>

#include "render/cli/commands.h"
#include "render/cli/lines_output.h"
#include "render/cli/options.h"
#include "render/cli/outcomes_output.h"
#include "render/cli/run_output.h"
#include "render/progress.h"
#include "sim/bake.h"
#include "sim/core/error.h"
#include "sim/recorder.h"
#include "sim/run_guard.h"
#include "sim/scene/scene.h"
#include "sim/shape/sphere_tree.h"

namespace vf::cli {
namespace {

struct SimulateOptions {
  std::string scene;
  std::string csv;
  std::string summary;
  std::string bake;
  std::string outcomes;
  std::string lines;         // --lines DIR: the evaluation lines' files
  std::string barriers;      // --barriers FILE: per-barrier results
  SceneOverrides overrides;  // --level, --step, --collider, run limits, --repair
  bool quiet = false;
  bool overwrite = false;       // -y
  bool neverOverwrite = false;  // -n
};

int runSimulate(const SimulateOptions& o) {
  SceneSpec spec = loadScene(o.scene);
  applyOverrides(spec, o.overrides);

  // Outputs: checked and opened before the expensive part (each is a temporary file until the
  // end; see render/output/output_file.h).
  const OutputRules rules = runOutputRules(spec, o.scene, o.overwrite, o.neverOverwrite);
  const std::pair<const char*, const std::string*> named[] = {
      {"--csv", &o.csv}, {"--summary", &o.summary}, {"--bake", &o.bake}};
  for (const auto& [a, pa] : named)
    for (const auto& [b, pb] : named)
      if (a < b && !pa->empty() && *pa == *pb)
        throw InputError("", std::string(a) + " and " + b + " name the same file '" + *pa + "'");
  std::optional<OutputFile> csv, summary, bakeFile;
  if (!o.csv.empty()) csv.emplace(o.csv, rules);
  if (!o.summary.empty()) summary.emplace(o.summary, rules);
  if (!o.bake.empty()) bakeFile.emplace(o.bake, rules);
  std::optional<OutputFile> outcomes;
  const bool geojson = o.outcomes.ends_with(".geojson") || o.outcomes.ends_with(".json");
  if (!o.outcomes.empty()) {
    for (const auto& [name, other] : named)
      if (o.outcomes == *other)
        throw InputError(
            "", std::string("--outcomes and ") + name + " name the same file '" + o.outcomes + "'");
    if (spec.terrainPath.empty())
      throw InputError(spec.path, "--outcomes needs a scene with terrain ([ground] heightfield)");
    outcomes.emplace(o.outcomes, rules);
  }
  std::optional<LineFiles> lineFiles;
  if (!o.lines.empty()) {
    if (spec.evaluationLines.empty())
      throw InputError(spec.path, "--lines needs [[evaluation_lines]] in the scene");
    lineFiles.emplace(o.lines, rules, true);
  }
  std::optional<OutputFile> barriersFile;
  if (!o.barriers.empty()) {
    if (spec.barriers.empty())
      throw InputError(spec.path, "--barriers needs [[barriers]] in the scene");
    barriersFile.emplace(o.barriers, rules);
  }
  installStopHandlers();

  BuiltScene built = buildScene(spec);
  Recorder recorder(*built.world, spec.fps, spec.duration);
  if (csv) writeCsvHeader(csv->stream());
  std::optional<Bake> bake;
  if (bakeFile) {
    bake = bakeHeader(spec, built);
    addBakeRecord(*bake, *built.world);  // t = 0, before the first step
  }
  // Decided on the last step at or before each frame (Recorder::setRunEnds).
  recorder.setRunEnds([&] {
    return !built.world->stopReason().empty() ||
           (spec.stopWhenSettled && built.world->allSettled());
  });
  // Crossings are found on the world's steps, not on the frames (sim/ground/evaluation_lines.h).
  std::optional<CrossingRecorder> crossings;
  if (lineFiles) {
    crossings.emplace(built.evaluationLines);
    crossings->observe(*built.world);
  }
  if (bake || crossings)
    recorder.setAfterStep([&] {
      if (bake) addBakeRecord(*bake, *built.world);
      if (crossings) crossings->observe(*built.world);
    });

  // Frame by frame; a stop signal ends the run after the frame in hand (output_file.h).
  Progress progress(spec.name, recorder.frameCount(), !o.quiet);
  int done = 0;
  std::string runaway;  // set when the run guard stopped the run (sim/run_guard.h)
  for (int k = 0; k < recorder.frameCount() && !stopSignal(); ++k) {
    try {
      recorder.advanceToFrame(k);
    } catch (const RunawayError& e) {
      // The frames so far are whole frames of a valid run up to the trouble: they are kept.
      runaway = e.what();
      break;
    }
    if (csv)
      writeCsvFrame(csv->stream(), k, recorder.frameTime(k), *built.world, recorder.frameStates(),
                    recorder.frameActive());
    done = k + 1;
    progress.update(done, recorder.frameTime(k));
    // Rock fall: the run ends when every rock has stopped or left (`stop = "all_at_rest"`),
    // or when a rock reached a terrain edge whose policy is "stop".
    if (recorder.runEnded()) break;
  }
  progress.finish();
  if (!runaway.empty()) {
    // The rows and records of the complete frames are a valid run up to the trouble and are
    // kept (a bake of them shows what went wrong); a summary or outcomes would pass for those of
    // a finished run, so they are not written.
    if (csv) csv->commit();
    if (bakeFile && done > 0) {
      bake->scene.duration = recorder.frameTime(done - 1);
      writeBake(bakeFile->stream(), o.bake, *bake);
      bakeFile->commit();
    }
    throw InputError(spec.path, runaway);
  }
  const int stop = stopSignal();
  if (stop && done == 0) {
    std::fprintf(stderr, "voxfall: interrupted before the first frame; no output written\n");
    return 128 + stop;  // the OutputFiles' destructors remove their temporary files
  }
  for (const std::string& m : built.world->terrainMessages())
    std::fprintf(stderr, "voxfall: warning: %s\n", m.c_str());
  if (!built.world->stopReason().empty())
    std::fprintf(stderr, "voxfall: run stopped at t = %.4f s: %s\n", built.world->time(),
                 built.world->stopReason().c_str());

  const RunSummary& result = recorder.summary();
  std::string written;
  const auto wrote = [&written](OutputFile& f) {
    f.commit();
    written += (written.empty() ? "" : ", ") + f.path();
  };
  if (outcomes) {
    if (geojson)
      writeOutcomesGeoJson(outcomes->stream(), *built.world);
    else
      writeOutcomesCsv(outcomes->stream(), *built.world);
    wrote(*outcomes);
  }
  if (lineFiles) {
    std::int64_t rocks = 0;
    for (const RockOutcome& r : built.world->outcomes()) rocks += r.released ? 1 : 0;
    lineFiles->write(built.evaluationLines, crossings->crossings(), rocks,
                     built.world->def().terrain->shift);
    written += (written.empty() ? "" : ", ") + o.lines;
  }
  if (barriersFile) {
    std::vector<std::int64_t> failed;
    for (const BarrierResult& r : built.barriers->results()) failed.push_back(r.failed ? 1 : 0);
    writeBarriersCsv(barriersFile->stream(), built.barriers->barriers(), built.barriers->results(),
                     failed);
    wrote(*barriersFile);
  }
  if (summary) {
    // An interrupted run's summary says so, and up to which frame it holds.
    const RunInterruption cut{stop, stop ? recorder.frameTime(done - 1) : 0.0};
    writeSummaryJson(summary->stream(), spec.name, result, cut);
    wrote(*summary);
  }
  if (csv) wrote(*csv);
  if (bakeFile) {
    bake->summary = result;
    // An interrupted (or settled, `stop = "all_at_rest"`) bake ends at its last frame, so it
    // renders only what was simulated.
    if (done < recorder.frameCount()) bake->scene.duration = recorder.frameTime(done - 1);
    writeBake(bakeFile->stream(), o.bake, *bake);
    wrote(*bakeFile);
  }
  printSummary(stdout, spec.name, result);
  if (!spec.terrainPath.empty()) {
    int count[4] = {0, 0, 0, 0};
    for (const RockOutcome& r : built.world->outcomes())
      if (r.released) ++count[static_cast<int>(r.state)];
    std::printf(
        "  rocks: %d stopped, %d left the terrain, %d buried, %d still moving (t = %.3f s)\n",
        count[1], count[2], count[3], count[0], built.world->time());
    // The outcomes of rocks cut off by the duration are where they were then, which reads
    // like a runout unless told (an interrupted run says so below instead).
    if (outcomes && count[0] > 0 && !stop)
      std::fprintf(stderr,
                   "voxfall: warning: %d of %d rocks were still moving at the end (t = %.4g s); "
                   "%s records them where they were then, not where they stop: raise "
                   "[simulation] duration\n",
                   count[0], count[0] + count[1] + count[2] + count[3], built.world->time(),
                   o.outcomes.c_str());
  }
  if (stop) {
    std::fprintf(stderr, "voxfall: interrupted; frames 0..%d (t = 0 .. %.6g s) written%s%s\n",
                 done - 1, recorder.frameTime(done - 1), written.empty() ? "" : " to ",
                 written.c_str());
    return 128 + stop;  // 130 for SIGINT, 143 for SIGTERM, as the shell would say
  }
  return 0;
}

}  // namespace

void addSimulateCommand(CLI::App& app, int& exitCode) {
  // Owned by the callback: CLI11 fills it during parse, after this function has returned.
  auto o = std::make_shared<SimulateOptions>();
  CLI::App* sub = app.add_subcommand(
      "simulate", "Step a scene through its frames without drawing; report the checksum");
  sub->add_option("SCENE", o->scene, "scene file (TOML)")->required()->type_name("");
  sub->add_option("--csv", o->csv,
                  "write every active body's state at every frame to this CSV file")
      ->type_name("FILE");
  sub->add_option("--summary", o->summary, "write the run summary to this JSON file")
      ->type_name("FILE");
  sub->add_option("--bake", o->bake,
                  "write the run (every body's state after every step, and what drawing needs) "
                  "to this file, for `voxfall render FILE` and `voxfall export FILE`")
      ->type_name("FILE");
  sub->add_option("--outcomes", o->outcomes,
                  "write per-rock outcomes (rock fall on terrain) to this file: CSV, or GeoJSON "
                  "when it ends in .geojson")
      ->type_name("FILE");
  sub->add_option("--lines", o->lines,
                  "write the crossings of the scene's [[evaluation_lines]] to this folder: "
                  "crossings.csv, lines.csv, lines.png (histograms), lines_profile.png")
      ->type_name("DIR");
  sub->add_option("--barriers", o->barriers,
                  "write per-barrier results of the scene's [[barriers]] to this CSV file: hits, "
                  "rocks stopped and passed, largest energy at a hit, failure")
      ->type_name("FILE");
  addPhysicsOptions(*sub, o->overrides);
  addThreadsOption(*sub, o->overrides);
  sub->add_flag("--quiet,-q", o->quiet, "no progress line on stderr");
  addOverwriteFlags(*sub, o->overwrite, o->neverOverwrite);
  sub->callback([o, &exitCode] { exitCode = runSimulate(*o); });
}

}  // namespace vf::cli

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
#include "render/cli/run_options.h"
#include "render/cli/run_output.h"
#include "sim/core/error.h"
#include "sim/recorder.h"
#include "sim/scene/scene.h"
#include "sim/shape/sphere_tree.h"

namespace vf::cli {
namespace {

struct SimulateOptions {
  std::string scene;
  std::string csv;
  std::string summary;
  std::optional<int> level;
  std::string step;
  bool quiet = false;
  RunOptions run;
};

int runSimulate(const SimulateOptions& o) {
  SceneSpec spec = loadScene(o.scene);
  if (o.level) applyLevelOverride(spec, *o.level);
  if (!o.step.empty()) applyStepOverride(spec, o.step);
  applyRunOptions(spec, o.run);

  if (!o.csv.empty() && o.csv == o.summary)
    throw InputError("", "--csv and --summary name the same file '" + o.csv + "'");
  std::optional<OutputFile> csv, summary;
  if (!o.csv.empty()) csv.emplace(o.csv);
  if (!o.summary.empty()) summary.emplace(o.summary);

  BuiltScene built = buildScene(spec);
  Recorder recorder(*built.world, spec.fps, spec.duration);
  if (csv) writeCsvHeader(csv->stream());

  Progress progress(spec.name, recorder.frameCount(), !o.quiet);
  try {
    for (int k = 0; k < recorder.frameCount(); ++k) {
      recorder.advanceToFrame(k);
      if (csv) writeCsvFrame(csv->stream(), k, recorder.frameTime(k), *built.world);
      progress.update(k + 1, recorder.frameTime(k));
    }
  } catch (const RunawayError& e) {
    // The rows so far are whole frames of a valid run up to the trouble: keep them.
    progress.finish();
    if (csv) csv->commit();
    throw InputError(spec.path, e.what());
  }
  progress.finish();

  const RunSummary& result = recorder.summary();
  if (summary) {
    writeSummaryJson(summary->stream(), spec.name, result);
    summary->commit();
  }
  if (csv) csv->commit();
  printSummary(stdout, spec.name, result);
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
  sub->add_option("--level", o->level,
                  "voxel level Lv for every shape (overrides the scene's levels)")
      ->type_name("N")
      ->check(CLI::Range(kMinLevel, kMaxLevel));
  sub->add_option("--step", o->step,
                  "time step: 'auto' (eq. 20) or seconds, e.g. 0.005 or 1/120 (overrides the scene)")
      ->check(CLI::Validator(
          [](std::string& text) { return checkStepOption(text); }, "", "STEP"))
      ->type_name("S|auto");
  sub->add_flag("--quiet,-q", o->quiet, "no progress line on stderr");
  addRunOptions(*sub, o->run);
  sub->callback([o, &exitCode] { exitCode = runSimulate(*o); });
}

}  // namespace vf::cli

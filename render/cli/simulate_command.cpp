// voxfall simulate SCENE: options into a SimulateRequest; the run (stepping, outputs, stop
// policy) is render/run/simulate_run.h.
#include <CLI/CLI.hpp>
#include <memory>

#include "render/cli/commands.h"
#include "render/cli/options.h"
#include "render/run/simulate_run.h"

namespace vf::cli {

void addSimulateCommand(CLI::App& app, int& exitCode) {
  // Owned by the callback: CLI11 fills it during parse, after this function has returned.
  auto o = std::make_shared<SimulateRequest>();
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
  sub->callback([o, &exitCode] { exitCode = vf::exitCode(runSimulation(*o)); });
}

}  // namespace vf::cli

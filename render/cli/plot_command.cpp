// voxfall plot RUN.csv [--scene SCENE] [-o DIR]: publication plots of a run written by
// `voxfall simulate --csv RUN.csv` (render/figures/run_plots.h). The CSV holds positions and
// velocities but not masses: with --scene the energies are in joules (masses and inertia from
// the scene's shapes), without it per kg and translational only, and the plots say so.
#include <CLI/CLI.hpp>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>

#include "render/cli/commands.h"
#include "render/figures/run_plots.h"
#include "render/run/run_output.h"
#include "sim/scene/scene.h"

namespace vf::cli {
namespace {

struct PlotOptions {
  std::string run;
  std::string scene;
  std::string outDir;
};

int runPlot(const PlotOptions& o) {
  fig::RunPlotOptions p;
  const std::string stem = std::filesystem::path(o.run).stem().string();
  p.outDir = o.outDir.empty() ? "out/plots/" + stem : o.outDir;
  p.title = stem;
  if (!o.scene.empty()) {
    SceneSpec spec = loadScene(o.scene);
    applyLevelOverride(spec, 1);  // mass properties do not depend on the level: build cheaply
    const BuiltScene built = buildScene(spec);
    for (int id = 0; id < built.world->bodyCount(); ++id) {
      const Shape& s = built.world->shape(id);
      const bool still = built.world->isStatic(id);
      p.bodies.push_back({still ? 0.0 : s.mass, still ? Mat3(Mat3::Zero()) : s.inertiaBody});
    }
    p.gravity = spec.gravity;
    p.title = spec.name;
    p.inputs = runOutputRules(spec, o.scene, false, false).inputs;  // scene, meshes: never written
  }
  fig::plotRun(o.run, p);
  std::printf("plots written to %s (energy, speed, trajectories: PNG, SVG; CSV data)\n",
              p.outDir.c_str());
  return 0;
}

}  // namespace

void addPlotCommand(CLI::App& app, int& exitCode) {
  auto o = std::make_shared<PlotOptions>();
  CLI::App* sub = app.add_subcommand(
      "plot", "Plot a run's energy, speeds and trajectories (from simulate --csv) as PNG and SVG");
  sub->add_option("RUN", o->run, "run CSV written by voxfall simulate --csv")
      ->required()
      ->type_name("RUN.csv");
  sub->add_option("--scene", o->scene, "the run's scene, for masses (energies in J)")
      ->type_name("SCENE");
  sub->add_option("-o,--output", o->outDir, "output folder (default: out/plots/<RUN stem>)")
      ->type_name("DIR");
  sub->callback([o, &exitCode] { exitCode = runPlot(*o); });
}

}  // namespace vf::cli

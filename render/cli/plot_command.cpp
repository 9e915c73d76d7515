// voxfall plot RUN.csv [--scene SCENE] [-o DIR]: options into a PlotRequest; the plots are
// render/run/plot_run.h.
#include <CLI/CLI.hpp>
#include <memory>

#include "render/cli/commands.h"
#include "render/run/plot_run.h"

namespace vf::cli {

void addPlotCommand(CLI::App& app, int& exitCode) {
  auto o = std::make_shared<PlotRequest>();
  CLI::App* sub = app.add_subcommand(
      "plot", "Plot a run's energy, speeds and trajectories (from simulate --csv) as PNG and SVG");
  sub->add_option("RUN", o->run, "run CSV written by voxfall simulate --csv")
      ->required()
      ->type_name("RUN.csv");
  sub->add_option("--scene", o->scene, "the run's scene, for masses (energies in J)")
      ->type_name("SCENE");
  sub->add_option("-o,--output", o->outDir, "output folder (default: out/plots/<RUN stem>)")
      ->type_name("DIR");
  sub->callback([o, &exitCode] { exitCode = vf::exitCode(runPlot(*o)); });
}

}  // namespace vf::cli

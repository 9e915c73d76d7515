// voxfall figures [NAME...] [-o DIR] [--quick]: options into a FiguresRequest; the figures are
// render/run/figures_run.h.
#include <CLI/CLI.hpp>
#include <memory>

#include "render/cli/commands.h"
#include "render/figures/paper_figures.h"
#include "render/run/figures_run.h"

namespace vf::cli {

void addFiguresCommand(CLI::App& app, int& exitCode) {
  auto o = std::make_shared<FiguresRequest>();
  CLI::App* sub = app.add_subcommand(
      "figures", "Reproduce the paper's comparisons (figs. 10, 13, 14, 16) as PNG, SVG and CSV");
  sub->add_option("NAME", o->names, "figures to make: fig10 fig13 fig14 fig16 (default: all)")
      ->check(CLI::IsMember(fig::paperFigureNames()));
  sub->add_option("-o,--output", o->outDir, "output folder (default: out/figures)")
      ->type_name("DIR");
  sub->add_option("--scenes", o->scenes, "folder of the paper's scenes (default: scenes/)")
      ->type_name("DIR");
  sub->add_flag("--quick", o->quick, "reduced configurations that run in seconds");
  sub->add_flag("--quiet,-q", o->quiet, "no progress lines on stderr");
  sub->callback([o, &exitCode] { exitCode = vf::exitCode(runFigures(*o)); });
}

}  // namespace vf::cli

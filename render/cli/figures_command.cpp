// voxfall figures [NAME...] [-o DIR] [--quick]: the paper's comparison figures (fig10, fig13,
// fig14, fig16) as PNG + SVG + CSV and DIR/README.md (render/figures/paper_figures.h).
#include <CLI/CLI.hpp>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "render/cli/commands.h"
#include "render/figures/paper_figures.h"

#ifndef VOXFALL_SCENES_DIR
#define VOXFALL_SCENES_DIR "scenes"
#endif

namespace vf::cli {
namespace {

struct FiguresOptions {
  std::vector<std::string> names;
  std::string outDir = "out/figures";
  std::string scenes;
  bool quick = false;
  bool quiet = false;
};

int runFigures(const FiguresOptions& o) {
  fig::PaperFigureOptions p;
  p.outDir = o.outDir;
  p.quick = o.quick;
  p.progress = !o.quiet;
  // The shipped scenes: ./scenes when run from the repository, else the source tree's.
  p.scenesDir = !o.scenes.empty()                              ? o.scenes
                : std::filesystem::exists("scenes/cubes.toml") ? "scenes"
                                                               : VOXFALL_SCENES_DIR;
  fig::makePaperFigures(o.names, p);
  std::printf("figures written to %s (README.md describes them)\n", o.outDir.c_str());
  return 0;
}

}  // namespace

void addFiguresCommand(CLI::App& app, int& exitCode) {
  auto o = std::make_shared<FiguresOptions>();
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
  sub->callback([o, &exitCode] { exitCode = runFigures(*o); });
}

}  // namespace vf::cli

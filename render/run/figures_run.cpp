#include "render/run/figures_run.h"

#include <cstdio>
#include <filesystem>

#include "render/figures/paper_figures.h"

#ifndef VOXFALL_SCENES_DIR
#define VOXFALL_SCENES_DIR "scenes"
#endif

namespace vf {

RunStatus runFigures(const FiguresRequest& o) {
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
  return RunStatus::done();
}

}  // namespace vf

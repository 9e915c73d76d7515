// The paper's comparisons (figs. 10, 13, 14, 16; digest sections 6-8) reproduced by running the
// shipped scenes through the library: voxel levels and the polygon method at the paper's steps,
// compute time (median of repeats, measured in the same run), the true-mesh interpenetration
// diagnostic, each figure as PNG + SVG + CSV, and a README.md with the tables.
#pragma once

#include <string>
#include <vector>

#include "sim/scene/scene.h"

namespace vf::fig {

struct PaperFigureOptions {
  std::string outDir = "out/figures";
  std::string scenesDir;  // folder holding cubes.toml, blocks.toml, ...
  bool quick = false;     // reduced configurations: seconds, for tests and a first look
  bool progress = true;   // progress lines with an ETA on stderr
};

// A run counts as interpenetrating when the true meshes overlap deeper than this at any output
// frame (body-body or body-ground), m. The same threshold for both methods.
constexpr double kInterpenetrationThreshold = 0.005;

// The CPU model from /proc/cpuinfo ("unknown CPU" without one): timing figures name it.
std::string cpuModel();

// "fig10", "fig13", "fig14", "fig16".
const std::vector<std::string>& paperFigureNames();

// One run of a figure: a shipped scene at a voxel level, step and contact method.
struct RunConfig {
  std::string scene;  // file stem in the scenes folder
  int level = 4;
  double step = 0;  // s; 0: eq. 20
  ColliderMethod collider = ColliderMethod::kVoxel;
  int repeats = 1;
};

// Every run figure `name` makes (the full set, or --quick's), one repeat each: what the tests
// check the paper's scenes under.
std::vector<RunConfig> paperFigureRuns(const std::string& name, bool quick);

// The scene `config.scene` from `scenesDir` as that run simulates it: its level, step and
// contact method. Throws InputError as loadScene does.
SceneSpec figureRunSpec(const std::string& scenesDir, const RunConfig& config);

// Makes the named figures (all when `names` is empty; unknown names throw InputError) in
// options.outDir, with OUT/README.md describing them.
void makePaperFigures(const std::vector<std::string>& names, const PaperFigureOptions& options);

}  // namespace vf::fig

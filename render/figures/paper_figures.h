// The paper's comparisons (figs. 10, 13, 14, 16; digest sections 6-8) reproduced by running the
// shipped scenes through the library: voxel levels and the polygon method at the paper's steps,
// compute time (median of repeats, measured in the same run), the true-mesh interpenetration
// diagnostic, each figure as PNG + SVG + CSV, and a README.md with the tables.
#pragma once

#include <string>
#include <vector>

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

// Makes the named figures (all when `names` is empty; unknown names throw InputError) in
// options.outDir, with OUT/README.md describing them.
void makePaperFigures(const std::vector<std::string>& names, const PaperFigureOptions& options);

}  // namespace vf::fig

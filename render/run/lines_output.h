// What a run writes of its evaluation lines (docs/rockfall.md, "Evaluation lines"), shared by
// `voxfall simulate --lines DIR` and `voxfall ensemble` so both write the same files the same
// way: crossings.csv (every crossing), lines.csv (per line: counts, probability, percentiles)
// and, with plots, lines.png (histograms) and lines_profile.png (along each line). Coordinates
// are the DEM file's own (the scene's offset undone). Every file goes through OutputFile.
#pragma once

#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "render/output/output_file.h"
#include "sim/ground/barriers.h"
#include "sim/ground/evaluation_lines.h"

namespace vf {

// One row per crossing, in the order given: line, name, rock, time (s), x, y, z (m, DEM file
// coordinates), vx, vy, vz (m/s), speed (m/s), translational, rotational and total kinetic
// energy (kJ), passing height (m; empty over no ground), direction (+1 left to right, -1 back).
// Numbers in their shortest exact text (number_text.h: they read back bit-exact).
void writeCrossingsCsv(std::FILE* out, const std::vector<EvaluationLine>& lines,
                       const std::vector<LineCrossing>& crossings, const Vec3& shift);
// One row per line: line, name, crossings, rocks_crossing, rocks, probability, energy_p50_kj,
// energy_p95_kj, energy_p99_kj, height_p50, height_p95, height_p99 (empty where NaN).
void writeLinesCsv(std::FILE* out, const std::vector<LineSummary>& summaries);

// One row per barrier: barrier, name, capacity_kj, hits, stopped, passed, max_energy_kj (empty
// without hits), failed (the runs or realisations in which a rock broke through it). `results`
// are summed over realisations (BarrierResult::failed counted in `failures`).
void writeBarriersCsv(std::FILE* out, const std::vector<Barrier>& barriers,
                      const std::vector<BarrierResult>& results,
                      const std::vector<std::int64_t>& failures);

class LineFiles {
 public:
  // Checks and opens the files in `dir` before the run (an existing one under -n, a file the
  // run reads: InputError).
  LineFiles(const std::filesystem::path& dir, const OutputRules& rules, bool plots);
  ~LineFiles();
  // Writes every file: `rocks` is how many rocks could cross (released bodies or complete
  // realisations); `shift` is the DEM's (world = file + shift). Returns the file names written,
  // ", "-separated.
  std::string write(const std::vector<EvaluationLine>& lines,
                    const std::vector<LineCrossing>& crossings, std::int64_t rocks,
                    const Vec3& shift);

 private:
  std::filesystem::path dir_;
  OutputRules rules_;
  bool plots_;
  std::unique_ptr<OutputFile> crossings_, summary_;
};

}  // namespace vf

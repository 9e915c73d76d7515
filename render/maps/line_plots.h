// Plots of the crossings of evaluation lines (docs/rockfall.md, "Evaluation lines"): per line, a
// histogram of the kinetic energy and one of the passing height, and the profile of both along
// the line. Drawn by gnuplot through render/figures/gnuplot.h, one PNG each, written through an
// OutputFile.
#pragma once

#include <string>
#include <vector>

#include "render/output/output_file.h"
#include "sim/ground/evaluation_lines.h"

namespace vf {

// The number of histogram bins for n values: the square-root choice ceil(sqrt(n)), kept within
// 5 .. 40 so that a few crossings still show a shape and many do not make needles.
int histogramBins(std::size_t n);

// One row per line: the histogram of the total kinetic energy (kJ) of its crossings and that of
// their passing heights (m), each with its 50th, 95th and 99th percentiles (`summaries`) marked.
// A line without crossings says so in its panels. Throws InputError if gnuplot fails or the path
// cannot be written under `rules`.
void writeLineHistograms(const std::vector<EvaluationLine>& lines,
                         const std::vector<LineSummary>& summaries,
                         const std::vector<LineCrossing>& crossings, const std::string& pngPath,
                         const OutputRules& rules = replaceOutputs());

// One row per line: the energy (kJ) and the passing height (m) of each crossing against its
// distance along the line from the line's first vertex (m, measured along the polyline).
void writeLineProfiles(const std::vector<EvaluationLine>& lines,
                       const std::vector<LineCrossing>& crossings, const std::string& pngPath,
                       const OutputRules& rules = replaceOutputs());

// The distance along `line` (from its first vertex, along the polyline, m) of the point of the
// polyline nearest to world (x, y).
double distanceAlong(const EvaluationLine& line, double x, double y);

}  // namespace vf

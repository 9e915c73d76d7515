#include "render/maps/line_plots.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <limits>
#include <sstream>

#include "render/figures/gnuplot.h"
#include "sim/core/error.h"

namespace vf {
namespace {

// Rows tall enough that a lower panel's title clears the upper panel's axis label (the
// multiplot's spacing is a fraction of the figure).
constexpr int kRowHeightPx = 400, kWidthPx = 1000;

// The histogram of `values` as CSV rows (bin centre, count) in `csv`; returns the bin width.
// No values: one empty bin on [0, 1].
double writeHistogram(const std::vector<double>& values, const std::string& csv,
                      const std::string& pngPath) {
  std::ofstream o(csv);
  o << std::setprecision(15) << "centre,count\n";
  if (values.empty()) {
    o << "0.5,0\n";
    if (!o) throw InputError(pngPath, "cannot write the temporary file " + csv);
    return 1;
  }
  const auto [low, high] = std::minmax_element(values.begin(), values.end());
  // Equal values: one bin a tenth of their size wide (or 1 when they are 0), centred on them.
  const bool spread = *high > *low;
  const int bins = spread ? histogramBins(values.size()) : 1;
  const double width = spread ? (*high - *low) / bins : (*low != 0 ? 0.1 * std::abs(*low) : 1.0);
  const double lo = spread ? *low : *low - width / 2;
  std::vector<int> count(static_cast<std::size_t>(bins), 0);
  for (double v : values)
    ++count[static_cast<std::size_t>(std::min(bins - 1, static_cast<int>((v - lo) / width)))];
  for (int k = 0; k < bins; ++k) o << lo + (k + 0.5) * width << "," << count[k] << "\n";
  if (!o) throw InputError(pngPath, "cannot write the temporary file " + csv);
  return width;
}

// A histogram panel with the percentiles marked by dashed lines.
fig::Panel histogramPanel(const std::string& title, const std::string& xLabel,
                          const std::vector<double>& values, const std::array<double, 3>& marks,
                          const std::string& csv, const std::string& pngPath, int colour) {
  const double width = writeHistogram(values, csv, pngPath);
  fig::Panel p;
  p.title = title;
  p.xLabel = xLabel;
  p.yLabel = "Crossings";
  std::ostringstream box;
  box << std::setprecision(15) << "set boxwidth " << width * 0.9;
  p.settings.push_back(box.str());
  p.settings.push_back("set yrange [0:*]");
  p.settings.push_back("set xrange [0:*]");  // energies and heights are never negative
  p.settings.push_back("set key off");
  if (values.empty()) {
    p.settings.push_back("set label 10 'no crossings' at graph 0.5, graph 0.5 center");
  } else {
    for (std::size_t k = 0; k < marks.size(); ++k) {
      std::ostringstream a;
      a << std::setprecision(15) << "set arrow " << 10 + k << " from " << marks[k]
        << ", graph 0 to " << marks[k] << ", graph 1 nohead front dt 2 lc rgb '#000000'";
      p.settings.push_back(a.str());
    }
  }
  p.series.push_back(fig::Series{"", csv, "1:2", "boxes", colour});
  return p;
}

// A figure of one row of two panels per line.
fig::Figure lineFigure(std::size_t lines, const std::string& footnote) {
  fig::Figure f;
  f.width = kWidthPx;
  f.height = kRowHeightPx * static_cast<int>(std::max<std::size_t>(1, lines));
  f.rows = static_cast<int>(lines);
  f.footnote = footnote;
  return f;
}

std::string kJ(double joules) {
  std::ostringstream o;
  o << std::setprecision(3) << joules / 1000;
  return o.str();
}

}  // namespace

int histogramBins(std::size_t n) {
  return std::clamp(static_cast<int>(std::ceil(std::sqrt(static_cast<double>(n)))), 5, 40);
}

double distanceAlong(const EvaluationLine& line, double x, double y) {
  double best = std::numeric_limits<double>::infinity(), at = 0, walked = 0;
  for (std::size_t k = 0; k + 1 < line.points.size(); ++k) {
    const double ax = line.points[k][0], ay = line.points[k][1];
    const double ex = line.points[k + 1][0] - ax, ey = line.points[k + 1][1] - ay;
    const double len2 = ex * ex + ey * ey;
    const double u = len2 > 0 ? std::clamp(((x - ax) * ex + (y - ay) * ey) / len2, 0.0, 1.0) : 0;
    const double d = std::hypot(ax + u * ex - x, ay + u * ey - y);
    if (d < best) best = d, at = walked + u * std::sqrt(len2);
    walked += std::sqrt(len2);
  }
  return at;
}

void writeLineHistograms(const std::vector<EvaluationLine>& lines,
                         const std::vector<LineSummary>& summaries,
                         const std::vector<LineCrossing>& crossings, const std::string& pngPath,
                         const OutputRules& rules) {
  const fig::ScratchFolder scratch;
  fig::Figure f = lineFigure(
      lines.size(), "Dashed: 50th, 95th and 99th percentiles (nearest rank) over the crossings.");
  for (std::size_t l = 0; l < lines.size(); ++l) {
    std::vector<double> energy, height;
    for (const LineCrossing& c : crossings) {
      if (c.line != static_cast<std::int32_t>(l)) continue;
      energy.push_back(c.energy() / 1000);
      if (!std::isnan(c.height)) height.push_back(c.height);
    }
    const LineSummary& s = summaries[l];
    const std::array<double, 3> e{s.energy[0] / 1000, s.energy[1] / 1000, s.energy[2] / 1000};
    const std::string name = "'" + lines[l].name + "': ";
    const std::string stem = scratch.file("line" + std::to_string(l));
    f.panels.push_back(histogramPanel(
        name + std::to_string(s.crossings) + " crossings, p95 " + kJ(s.energy[1]) + " kJ",
        "Kinetic energy (kJ)", energy, e, stem + "_energy.csv", pngPath, 0));
    std::ostringstream t;
    t << std::setprecision(3) << name << "passing height, p95 " << s.height[1] << " m";
    f.panels.push_back(histogramPanel(t.str(), "Passing height of the centre (m)", height, s.height,
                                      stem + "_height.csv", pngPath, 1));
  }
  fig::drawFigurePng(f, pngPath, rules);
}

void writeLineProfiles(const std::vector<EvaluationLine>& lines,
                       const std::vector<LineCrossing>& crossings, const std::string& pngPath,
                       const OutputRules& rules) {
  const fig::ScratchFolder scratch;
  fig::Figure f = lineFigure(
      lines.size(), "Each point is one crossing, at its distance from the line's first vertex.");
  for (std::size_t l = 0; l < lines.size(); ++l) {
    const std::string csv = scratch.file("profile" + std::to_string(l) + ".csv");
    std::ofstream o(csv);
    o << std::setprecision(15) << "distance,energy_kj,height\n";
    double length = 0;
    for (std::size_t k = 0; k + 1 < lines[l].points.size(); ++k)
      length += std::hypot(lines[l].points[k + 1][0] - lines[l].points[k][0],
                           lines[l].points[k + 1][1] - lines[l].points[k][1]);
    bool any = false;
    for (const LineCrossing& c : crossings) {
      if (c.line != static_cast<std::int32_t>(l)) continue;
      o << distanceAlong(lines[l], c.point.x(), c.point.y()) << "," << c.energy() / 1000 << ","
        << (std::isnan(c.height) ? std::string("NaN") : std::to_string(c.height)) << "\n";
      any = true;
    }
    if (!any) o << "NaN,NaN,NaN\n";
    if (!o) throw InputError(pngPath, "cannot write the temporary file " + csv);
    std::ostringstream range;
    range << std::setprecision(15) << "set xrange [0:" << length << "]";
    for (int which = 0; which < 2; ++which) {
      fig::Panel p;
      p.title = "'" + lines[l].name + "': " + (which == 0 ? "kinetic energy" : "passing height");
      p.xLabel = "Distance along the line (m)";
      p.yLabel = which == 0 ? "Kinetic energy (kJ)" : "Passing height of the centre (m)";
      p.settings.push_back(range.str());
      p.settings.push_back("set key off");
      p.settings.push_back(any ? "set yrange [0:*]" : "set yrange [0:1]");
      if (!any) p.settings.push_back("set label 10 'no crossings' at graph 0.5, graph 0.5 center");
      p.series.push_back(fig::Series{"", csv, which == 0 ? "1:2" : "1:3", "points", which});
      f.panels.push_back(p);
    }
  }
  fig::drawFigurePng(f, pngPath, rules);
}

}  // namespace vf

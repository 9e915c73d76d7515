// gnuplot is driven with a script file (never by parsing its output): the script is written to
// a scratch folder of its own, gnuplot runs it once (a helper program of output_file.h, so a stop
// signal ends it with the run), writing the figure's files under the temporary names of their
// OutputFiles, which are renamed when gnuplot exits cleanly. A failure removes the temporaries and
// reports gnuplot's first error line.
#include "render/figures/gnuplot.h"

#include <unistd.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "render/output/output_file.h"
#include "sim/core/error.h"

namespace vf::fig {
namespace {

namespace fs = std::filesystem;

// Colour-blind-safe palette (Okabe & Ito), shared by every figure.
constexpr std::array<const char*, 7> kPalette{"#0072B2", "#D55E00", "#009E73", "#CC79A7",
                                              "#E69F00", "#56B4E9", "#000000"};

std::string seriesClause(const Series& s) {
  if (s.hollow && !s.title.empty())
    throw std::logic_error("series '" + s.title +
                           "' is hollow and has a legend entry: hollow marks mean "
                           "interpenetration; give the legend a filled keyOnly series");
  std::ostringstream o;
  const char* color = kPalette[static_cast<std::size_t>(s.color) % kPalette.size()];
  if (s.keyOnly)
    o << "keyentry with " << s.style;
  else
    o << gnuplotString(s.csv) << " using " << s.using_ << " with " << s.style;
  o << " lc rgb " << gnuplotString(color) << " lw 2";
  if (s.style == "boxes")  // the fill takes the line colour; the border is given again
    o << (s.hollow ? " fs empty border lc rgb " : " fs solid 0.75 border lc rgb ")
      << gnuplotString(color);
  if (s.style == "linespoints" || s.style == "points")
    o << " pt " << (s.hollow ? 6 : 7) << " ps 1.3";
  o << (s.title.empty() ? " notitle" : " title " + gnuplotString(s.title));
  return o.str();
}

// The plotting commands for one terminal (same for PNG and SVG).
std::string body(const Figure& f) {
  std::ostringstream o;
  o << "set datafile separator ','\n";
  if (!f.footnote.empty())
    o << "set label 1000 " << gnuplotString(f.footnote)
      << " at screen 0.01, screen 0.03 font ',9'\n";
  const int n = static_cast<int>(f.panels.size());
  const int rows = std::max(1, f.rows), columns = (n + rows - 1) / rows;
  // One row keeps its margins; a grid gives the rows the height the footnote and title leave,
  // in pixels, so that a lower panel's title clears the axis label of the panel above it and
  // the footnote clears the bottom row's label, whatever the figure's height.
  o << "set multiplot layout " << rows << "," << columns << " title " << gnuplotString(f.title)
    << " font ',13' margins 0.08,0.98,";
  if (rows == 1) {
    o << "0.2,0.86 spacing 0.09\n";
  } else {
    const double h = std::max(1, f.height);
    o << 95 / h << "," << 1 - 45 / h << " spacing 0.09," << 105 / h << "\n";
  }
  for (const Panel& p : f.panels) {
    o << "unset logscale\nunset xtics\nunset ytics\nset xtics nomirror\nset ytics nomirror\n"
      << "set grid lc rgb '#d0d0d0'\nset key top left box opaque\nset autoscale\n"
      << "set boxwidth 0.6\nset title " << gnuplotString(p.title) << "\nset xlabel "
      << gnuplotString(p.xLabel) << "\nset ylabel " << gnuplotString(p.yLabel) << "\n";
    if (p.logY) o << "set logscale y\n";
    if (p.logX) o << "set logscale x\n";
    for (const std::string& s : p.settings) o << s << "\n";
    o << "plot ";
    for (std::size_t i = 0; i < p.series.size(); ++i)
      o << (i ? ", \\\n     " : "") << seriesClause(p.series[i]);
    o << "\n";
  }
  o << "unset multiplot\n";
  return o.str();
}

// The pngcairo terminal every figure uses.
std::string pngTerminal(const Figure& f) {
  return "set terminal pngcairo noenhanced size " + std::to_string(f.width) + "," +
         std::to_string(f.height) + " font 'DejaVu Sans,11'\n";
}

}  // namespace

std::string gnuplotString(const std::string& s) {
  std::string out = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') out += '\\';
    out += c;
  }
  return out + "\"";
}

ScratchFolder::ScratchFolder() {
  // Process id plus a counter: two figures of one run, or two runs, never share a folder.
  static std::atomic<unsigned> counter{0};
  std::error_code ec;
  const fs::path base = fs::temp_directory_path(ec);
  std::string name = "voxfall-plot-";
  name += std::to_string(static_cast<long>(::getpid()));
  name += "-";
  name += std::to_string(counter++);
  const fs::path folder = (ec ? fs::path("/tmp") : base) / name;
  fs::remove_all(folder, ec);
  if (!fs::create_directories(folder, ec))
    throw InputError(folder.string(), "cannot create a temporary folder: " + ec.message());
  path_ = folder.string();
}

ScratchFolder::~ScratchFolder() {
  std::error_code ignored;
  fs::remove_all(path_, ignored);
}

std::string ScratchFolder::file(const std::string& name) const {
  return (fs::path(path_) / name).string();
}

void runGnuplot(const std::string& script, const std::string& where) {
  const ScratchFolder scratch;
  const std::string scriptPath = scratch.file("figure.gp"), log = scratch.file("gnuplot.log");
  {
    std::ofstream s(scriptPath);
    s << script;
    if (!s) throw InputError(where, "cannot write the gnuplot script " + scriptPath);
  }
  const int status = runHelperProgram({"gnuplot", scriptPath}, log);
  if (status == 0) return;
  std::string firstError;
  std::ifstream l(log);
  for (std::string line; std::getline(l, line);)
    if (!line.empty() && line.find_first_not_of(" ^") != std::string::npos) {
      firstError = line;
      break;
    }
  throw InputError(where,
                   "gnuplot failed (is gnuplot-nox installed?): " +
                       (firstError.empty() ? "exit status " + std::to_string(status) : firstError));
}

void drawFigure(const Figure& figure, const std::string& basePath) {
  OutputFile png(basePath + ".png", replaceOutputs()), svg(basePath + ".svg", replaceOutputs());
  png.closeStream();  // gnuplot writes the temporary files by name
  svg.closeStream();
  const std::string script = pngTerminal(figure) + "set output " + gnuplotString(png.tempPath()) +
                             "\n" + body(figure) + "set output\n" +
                             "set terminal svg noenhanced size " + std::to_string(figure.width) +
                             "," + std::to_string(figure.height) +
                             " font 'DejaVu Sans,11' dynamic background '#ffffff'\nset output " +
                             gnuplotString(svg.tempPath()) + "\n" + body(figure) + "set output\n";
  runGnuplot(script, basePath);
  std::error_code ec;
  if (fs::file_size(png.tempPath(), ec) == 0 || fs::file_size(svg.tempPath(), ec) == 0)
    throw InputError(basePath, "gnuplot failed (is gnuplot-nox installed?): no output written");
  png.commit();
  svg.commit();
}

void drawFigurePng(const Figure& figure, const std::string& pngPath, const OutputRules& rules) {
  OutputFile out(pngPath, rules);
  out.closeStream();  // gnuplot writes the temporary file by name
  runGnuplot(pngTerminal(figure) + "set output " + gnuplotString(out.tempPath()) + "\n" +
                 body(figure) + "set output\n",
             pngPath);
  out.commit();
}

}  // namespace vf::fig

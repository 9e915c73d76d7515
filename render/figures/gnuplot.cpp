// gnuplot is driven with a script file (never by parsing its output): the script is written
// next to the figure under a temporary name, gnuplot runs it once, writing both terminals'
// files under temporary names, and those are renamed when gnuplot exits cleanly. A failure
// removes the temporaries and reports gnuplot's first error line.
#include "render/figures/gnuplot.h"

#include <unistd.h>

#include <array>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "sim/core/error.h"

namespace vf::fig {
namespace {

namespace fs = std::filesystem;

// Colour-blind-safe palette (Okabe & Ito), shared by every figure.
constexpr std::array<const char*, 7> kPalette{"#0072B2", "#D55E00", "#009E73", "#CC79A7",
                                              "#E69F00", "#56B4E9", "#000000"};

// A gnuplot double-quoted string.
std::string quoted(const std::string& s) {
  std::string out = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') out += '\\';
    out += c;
  }
  return out + "\"";
}

// A shell single-quoted word.
std::string shellWord(const std::string& s) {
  std::string out = "'";
  for (char c : s) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

std::string seriesClause(const Series& s) {
  std::ostringstream o;
  const char* color = kPalette[static_cast<std::size_t>(s.color) % kPalette.size()];
  o << quoted(s.csv) << " using " << s.using_ << " with " << s.style;
  o << " lc rgb " << quoted(color) << " lw 2";
  if (s.style == "boxes")  // the fill takes the line colour; the border is given again
    o << (s.hollow ? " fs empty border lc rgb " : " fs solid 0.75 border lc rgb ") << quoted(color);
  if (s.style == "linespoints" || s.style == "points")
    o << " pt " << (s.hollow ? 6 : 7) << " ps 1.3";
  o << (s.title.empty() ? " notitle" : " title " + quoted(s.title));
  return o.str();
}

// The plotting commands for one terminal (same for PNG and SVG).
std::string body(const Figure& f) {
  std::ostringstream o;
  o << "set datafile separator ','\n";
  if (!f.footnote.empty())
    o << "set label 1000 " << quoted(f.footnote) << " at screen 0.01, screen 0.03 font ',9'\n";
  const int n = static_cast<int>(f.panels.size());
  o << "set multiplot layout 1," << n << " title " << quoted(f.title)
    << " font ',13' margins 0.08,0.98,0.2,0.86 spacing 0.09\n";
  for (const Panel& p : f.panels) {
    o << "unset logscale\nunset xtics\nunset ytics\nset xtics nomirror\nset ytics nomirror\n"
      << "set grid lc rgb '#d0d0d0'\nset key top left box opaque\nset autoscale\n"
      << "set boxwidth 0.6\nset title " << quoted(p.title) << "\nset xlabel " << quoted(p.xLabel)
      << "\nset ylabel " << quoted(p.yLabel) << "\n";
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

std::string partialName(const std::string& path) {
  const fs::path p(path);
  std::string name = ".";  // appended piecewise: GCC 12 warns wrongly on one long concatenation
  name += p.filename().string();
  name += ".partial-";
  name += std::to_string(::getpid());
  name += p.extension().string();
  return (p.parent_path() / name).string();
}

}  // namespace

void drawFigure(const Figure& figure, const std::string& basePath) {
  const std::string png = basePath + ".png", svg = basePath + ".svg";
  const std::string pngTmp = partialName(png), svgTmp = partialName(svg);
  const std::string script = partialName(basePath + ".gp");
  const std::string log = partialName(basePath + ".log");
  {
    std::ofstream s(script);
    s << "set terminal pngcairo noenhanced size " << figure.width << "," << figure.height
      << " font 'DejaVu Sans,11'\nset output " << quoted(pngTmp) << "\n"
      << body(figure) << "set output\n"
      << "set terminal svg noenhanced size " << figure.width << "," << figure.height
      << " font 'DejaVu Sans,11' dynamic background '#ffffff'\nset output " << quoted(svgTmp)
      << "\n"
      << body(figure) << "set output\n";
    if (!s) throw InputError(basePath, "cannot write the gnuplot script " + script);
  }
  const std::string command = "gnuplot " + shellWord(script) + " >" + shellWord(log) + " 2>&1";
  const int status = std::system(command.c_str());
  std::string firstError;
  {
    std::ifstream l(log);
    std::string line;
    while (std::getline(l, line))
      if (firstError.empty() && !line.empty() && line.find_first_not_of(" ^") != std::string::npos)
        firstError = line;
  }
  std::error_code ignored;
  fs::remove(script, ignored);
  fs::remove(log, ignored);
  if (status != 0 || !fs::exists(pngTmp) || !fs::exists(svgTmp)) {
    fs::remove(pngTmp, ignored);
    fs::remove(svgTmp, ignored);
    throw InputError(
        basePath, "gnuplot failed (is gnuplot-nox installed?): " +
                      (firstError.empty() ? "exit status " + std::to_string(status) : firstError));
  }
  fs::rename(pngTmp, png);
  fs::rename(svgTmp, svg);
}

}  // namespace vf::fig

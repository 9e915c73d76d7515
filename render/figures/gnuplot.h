// Figures drawn by gnuplot (Debian's gnuplot-nox: pngcairo and svg terminals), the one plotting
// dependency. Callers describe panels and series over CSV files; this file alone knows
// gnuplot's language and runs the gnuplot program. Every figure gets the same look: sans-serif
// 11 pt, the same palette, grid, legend and margins, PNG at 1 px per point and SVG.
#pragma once

#include <string>
#include <vector>

#include "render/output/output_file.h"

namespace vf::fig {

// One curve or bar set read from a CSV file with a header row.
struct Series {
  std::string title;                  // legend entry ("" for none)
  std::string csv;                    // path of the data file
  std::string using_;                 // gnuplot `using` expression, e.g. "1:2" or "0:5:xtic(4)"
  std::string style = "linespoints";  // "linespoints", "lines", "points", "boxes"
  int color = 0;                      // index into the shared palette
  // Open markers / unfilled boxes: in voxfall's figures they mean a run that interpenetrated,
  // so a hollow series never carries a legend entry (drawFigure refuses one); its legend entry
  // is a filled `keyOnly` series of the same colour.
  bool hollow = false;
  bool keyOnly = false;  // a legend entry alone (gnuplot's keyentry): no data is read
};

struct Panel {
  std::string title;
  std::string xLabel, yLabel;  // with units
  bool logY = false;
  bool logX = false;
  std::vector<Series> series;
  std::vector<std::string> settings;  // extra gnuplot `set ...` lines for this panel
};

struct Figure {
  std::string title;          // above all panels
  std::string footnote;       // small print under the panels (machine, threshold, ...)
  std::vector<Panel> panels;  // drawn side by side, in `rows` rows
  int rows = 1;
  int width = 1100, height = 480;  // px for PNG (points for SVG)
};

// Writes BASE.png and BASE.svg (through temporary names, renamed when gnuplot succeeded).
// Throws InputError naming gnuplot's complaint if it is missing or fails.
void drawFigure(const Figure& figure, const std::string& basePath);

// Writes `figure` as one PNG (no SVG) at `pngPath` through an OutputFile (temporary name,
// renamed when gnuplot succeeded) under `rules` (default: existing files are replaced). Throws
// InputError as drawFigure.
void drawFigurePng(const Figure& figure, const std::string& pngPath,
                   const OutputRules& rules = replaceOutputs());

// A folder of its own under the system's temporary folder for a figure's data files; removed
// with everything in it when destroyed.
class ScratchFolder {
 public:
  ScratchFolder();  // throws InputError if it cannot be created
  ~ScratchFolder();
  ScratchFolder(const ScratchFolder&) = delete;
  ScratchFolder& operator=(const ScratchFolder&) = delete;
  // The path of `name` inside the folder.
  std::string file(const std::string& name) const;

 private:
  std::string path_;
};

// Runs gnuplot once on `script` (gnuplot's language; it is written to a scratch file). Throws
// InputError(where, gnuplot's first error line) if gnuplot is missing or fails.
void runGnuplot(const std::string& script, const std::string& where);

// `s` as a gnuplot double-quoted string literal.
std::string gnuplotString(const std::string& s);

}  // namespace vf::fig

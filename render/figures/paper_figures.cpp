// The paper's comparison figures: the figures asked for, their runs planned for the progress's
// ETA, and the README.md that describes them (figure10.cpp and comparison_figures.cpp make the
// figures; figure_runs.cpp runs their configurations).
#include "render/figures/paper_figures.h"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "render/figures/figure_runs.h"
#include "sim/core/error.h"
#include "sim/scene/scene.h"

namespace vf::fig {
namespace {

namespace fs = std::filesystem;

// The first line of the README.md the figures write. The folder's other files have the
// figures' own names, but README.md is a name users give their files too: one that does not
// start with this line was not written here and is never replaced.
constexpr const char* kReadmeHeading = "# The paper's comparisons, reproduced";

void checkReadmeIsOurs(const std::string& path) {
  std::error_code ec;
  if (!fs::exists(path, ec)) return;
  std::ifstream in(path);
  std::string first;
  std::getline(in, first);
  if (first != kReadmeHeading)
    throw InputError(path,
                     "exists and was not written by voxfall figures; not replaced: choose "
                     "another output folder (-o) or move the file");
}

// Every run of figure `name`, in the order it makes them.
std::vector<RunConfig> runsOf(const std::string& name, bool quick, int repeats) {
  if (name == "fig10") return figure10Runs(quick, repeats);
  const std::vector<Comparison> rows = name == "fig13"   ? figure13Rows(quick, repeats)
                                       : name == "fig14" ? figure14Rows(quick, repeats)
                                       : name == "fig16" ? figure16Rows(quick, repeats)
                                                         : std::vector<Comparison>{};
  std::vector<RunConfig> runs;
  for (const Comparison& c : rows) runs.push_back(c.config);
  return runs;
}

}  // namespace

SceneSpec figureRunSpec(const std::string& scenesDir, const RunConfig& c) {
  SceneSpec spec = loadScene((fs::path(scenesDir) / (c.scene + ".toml")).string());
  applyLevelOverride(spec, c.level);
  spec.step = c.step > 0 ? StepRule::fixed(c.step) : StepRule::eq20();
  spec.collider = c.collider;
  spec.contactReduction = spec.sleep = false;  // the paper's method, whatever the file says
  return spec;
}

std::vector<RunConfig> paperFigureRuns(const std::string& name, bool quick) {
  return runsOf(name, quick, 1);
}

const std::vector<std::string>& paperFigureNames() {
  static const std::vector<std::string> names{"fig10", "fig13", "fig14", "fig16"};
  return names;
}

void makePaperFigures(const std::vector<std::string>& requested, const PaperFigureOptions& o) {
  std::vector<std::string> names = requested.empty() ? paperFigureNames() : requested;
  for (const std::string& n : names)
    if (std::find(paperFigureNames().begin(), paperFigureNames().end(), n) ==
        paperFigureNames().end())
      throw InputError("", "unknown figure '" + n + "' (known: fig10, fig13, fig14, fig16)");
  const std::string readme = (fs::path(o.outDir) / "README.md").string();
  checkReadmeIsOurs(readme);  // before minutes of runs
  std::error_code ec;
  fs::create_directories(o.outDir, ec);
  if (ec) throw InputError(o.outDir, "cannot create the output folder: " + ec.message());

  const int repeats = o.quick ? 1 : 3;
  RunProgress progress(o.progress);
  // Plan every run first, so the ETA covers the whole set from the start.
  for (const std::string& n : names) {
    const double duration = n == "fig10" ? 2.0 : n == "fig13" ? 5.0 : n == "fig14" ? 6.0 : 12.0;
    for (const RunConfig& c : runsOf(n, o.quick, repeats))
      progress.planned(expectedWork(c, duration));
  }
  std::vector<Section> sections;
  for (const std::string& n : names) {
    if (n == "fig10") sections.push_back(figure10(o, repeats, progress));
    if (n == "fig13") sections.push_back(figure13(o, repeats, progress));
    if (n == "fig14") sections.push_back(figure14(o, repeats, progress));
    if (n == "fig16") sections.push_back(figure16(o, repeats, progress));
  }
  std::ostringstream md;
  md << kReadmeHeading << "\n\n"
     << "Made by `voxfall figures" << (o.quick ? " --quick" : "") << "` on " << machineName()
     << ". Compute time is the stepping time (no loading, no drawing, no diagnostics), median "
        "of "
     << repeats << (repeats == 1 ? " run" : " runs")
     << " measured in this one invocation; the paper's times are MATLAB on a 2.4 GHz Pentium 4, "
        "so compare ratios, not seconds. Interpenetration is the true-mesh diagnostic of "
        "`voxfall simulate` (deepest surface sample of one mesh inside another, and deepest "
        "vertex below the floor) at every output frame, the same for both methods; a run "
        "counts as interpenetrating above "
     << mm(kInterpenetrationThreshold) << " mm." << (o.quick ? " `--quick`: reduced set." : "")
     << "\n\n";
  for (const Section& s : sections) md << s.markdown;
  writeText(readme, md.str());
}

std::string cpuModel() {
  std::ifstream cpu("/proc/cpuinfo");
  std::string line;
  while (std::getline(cpu, line))
    if (line.rfind("model name", 0) == 0) return line.substr(line.find(':') + 2);
  return "unknown CPU";
}

}  // namespace vf::fig

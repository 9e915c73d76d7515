// What the paper's figures share (paper_figures.cpp, figure10.cpp, comparison_figures.cpp): one
// run of a configuration with its compute time and diagnostics, the progress over all runs,
// the rows of the comparison figures, number formatting and each figure's README section.
// Private to render/figures.
#pragma once

#include <chrono>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include "render/figures/paper_figures.h"

namespace vf::fig {

struct RunResult {
  double seconds = 0;  // median compute time
  std::vector<double> samples;
  std::uint64_t steps = 0;
  double meanStep = 0;
  int bodies = 0;
  double penetrationBodyBody = 0, penetrationBodyGround = 0;  // m, max over frames
  std::uint64_t overlappingReleases = 0;  // bodies released into another body's spheres
  std::vector<Vec3> finalPositions;
  bool interpenetrated() const {
    return std::max(penetrationBodyBody, penetrationBodyGround) > kInterpenetrationThreshold;
  }
};

// Runs configuration `c` of a scene in `scenesDir` `c.repeats` times: the median compute time
// and, from the first run, the steps, the diagnostics and the final positions.
RunResult runScene(const std::string& scenesDir, const RunConfig& c);

// Progress over a list of runs with an ETA from the work done so far. A run's expected cost
// is its number of steps (duration / step; eq.-20 runs count as 1/200 s steps) times a factor
// for its method, learnt from the runs already done: good enough for "about N s left".
class RunProgress {
 public:
  RunProgress(bool enabled) : enabled_(enabled), start_(Clock::now()) {}
  void planned(double work) { total_ += work; }
  void done(const std::string& what, double work, const RunResult& r) {
    done_ += work;
    if (!enabled_) return;
    const double elapsed = std::chrono::duration<double>(Clock::now() - start_).count();
    const double left = done_ > 0 ? elapsed * (total_ - done_) / done_ : 0;
    std::fprintf(stderr,
                 "figures: %-42s %8.3f s (median of %zu)  elapsed %5.0f s, about %.0f s left\n",
                 what.c_str(), r.seconds, r.samples.size(), elapsed, left);
  }

 private:
  using Clock = std::chrono::steady_clock;
  bool enabled_;
  Clock::time_point start_;
  double total_ = 0, done_ = 0;
};

// A run's expected cost for the progress's ETA: its steps (eq.-20 runs count as 1/200 s steps)
// times its repeats.
double expectedWork(const RunConfig& c, double duration);

// The CPU model and its logical cores.
std::string machineName();
// `v` printed with a printf format.
std::string fmt(const char* format, double v);
// "1/120" for steps that are the reciprocal of a whole number, else seconds.
std::string stepText(double step);
// Writes a figure's text file (CSV, README), replacing the one there.
void writeText(const std::string& path, const std::string& text);
// Millimetres, one decimal.
std::string mm(double metres);
// The small print of a timing figure: what was timed, on what, and (for the comparisons) what
// a hollow marker means.
std::string footnote(int repeats, bool hollowMarkers);

// A figure's part of the README.md.
struct Section {
  std::string name;
  std::string markdown;
};

// --- comparison figures (13, 14, 16): one row per configuration ----------------------------

struct Comparison {
  std::string label;  // x tick / table row
  RunConfig config;
  int blocks = 0;  // fig. 16's x
  RunResult result;
};

// Fig. 10's runs: the reference at eq. 20, the paper's reference (full set only), the levels.
std::vector<RunConfig> figure10Runs(bool quick, int repeats);
Section figure10(const PaperFigureOptions& o, int repeats, RunProgress& progress);

// The rows of figs. 13, 14 and 16 (not yet run), and the figures made from them.
std::vector<Comparison> figure13Rows(bool quick, int repeats);
std::vector<Comparison> figure14Rows(bool quick, int repeats);
std::vector<Comparison> figure16Rows(bool quick, int repeats);
Section figure13(const PaperFigureOptions& o, int repeats, RunProgress& progress);
Section figure14(const PaperFigureOptions& o, int repeats, RunProgress& progress);
Section figure16(const PaperFigureOptions& o, int repeats, RunProgress& progress);

}  // namespace vf::fig

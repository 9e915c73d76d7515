// One run of a figure's configuration, through the library exactly as `voxfall simulate` runs
// it (loadScene -> overrides -> buildScene -> Recorder over every output frame), so the
// true-mesh diagnostics are measured at every frame for both methods alike.
//
// Compute time is the time spent stepping (the stage timers of StepStats: pairs, contacts,
// solve, integrate), without loading, shape building or the per-frame diagnostics: the paper's
// times exclude drawing, and the diagnostics are ours, not part of either method. Each
// configuration runs `repeats` times in this process and the median is reported; every repeat
// gives the same trajectory (determinism), only the clock differs.
#include "render/figures/figure_runs.h"

#include <algorithm>
#include <cmath>
#include <thread>

#include "render/output/output_file.h"
#include "sim/recorder.h"
#include "sim/scene/scene.h"

namespace vf::fig {
namespace {

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

}  // namespace

RunResult runScene(const std::string& scenesDir, const RunConfig& c) {
  SceneSpec spec = figureRunSpec(scenesDir, c);
  spec.stageTimes = true;  // compute time = the stages' timers
  RunResult r;
  for (int i = 0; i < c.repeats; ++i) {
    BuiltScene built = buildScene(spec);
    Recorder recorder(*built.world, spec.fps, spec.duration);
    recorder.advanceToFrame(recorder.frameCount() - 1);
    const RunStats& t = built.world->totals();
    r.samples.push_back(t.secondsPairs + t.secondsContacts + t.secondsSolve + t.secondsIntegrate);
    if (i > 0) continue;
    const RunSummary& s = recorder.summary();
    r.steps = t.steps;
    r.meanStep = spec.duration / static_cast<double>(t.steps);
    r.bodies = built.world->bodyCount();
    r.penetrationBodyBody = s.maxPenetrationBodyBody;
    r.penetrationBodyGround = s.maxPenetrationBodyGround;
    r.overlappingReleases = t.overlappingReleases;
    for (int b = 0; b < built.world->bodyCount(); ++b)
      r.finalPositions.push_back(built.world->state(b).x);
  }
  r.seconds = median(r.samples);
  return r;
}

double expectedWork(const RunConfig& c, double duration) {
  const double steps = duration / (c.step > 0 ? c.step : 1.0 / 200);
  return steps * c.repeats;
}

std::string machineName() {
  return cpuModel() + ", " + std::to_string(std::thread::hardware_concurrency()) + " logical cores";
}

std::string fmt(const char* format, double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, format, v);
  return buf;
}

// "1/120" for steps that are the reciprocal of a whole number, else seconds.
std::string stepText(double step) {
  if (step <= 0) return "eq. 20";
  const double inv = 1 / step;
  if (std::abs(inv - std::round(inv)) < 1e-6) return "1/" + std::to_string(std::lround(inv));
  return fmt("%.3g s", step);
}

void writeText(const std::string& path, const std::string& text) {
  // Figures and plots rewrite their own output folder, as reports do.
  OutputFile out(path, replaceOutputs());
  std::fputs(text.c_str(), out.stream());
  out.commit();
}

std::string mm(double metres) { return fmt("%.1f", metres * 1000); }

// The small print of a timing figure: what was timed, on what, and (for the comparisons) what
// a hollow marker means.
std::string footnote(int repeats, bool hollowMarkers) {
  std::string text = "compute time: stepping only, median of " + std::to_string(repeats) +
                     (repeats == 1 ? " run" : " runs") + "; machine: " + machineName() + ".";
  if (hollowMarkers)
    text += " Hollow: the true meshes interpenetrate deeper than " +
            mm(kInterpenetrationThreshold) + " mm at some frame.";
  return text;
}

}  // namespace vf::fig

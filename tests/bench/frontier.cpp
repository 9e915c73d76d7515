// The accuracy-cost frontier (frontier.h). Per scene, voxfall at levels 2-6 with eq. 20 and
// with the clearance step, each as the paper's method and the fast one (contact reduction and
// sleeping), and Bullet at 1, 2, 4, 8 and 16 steps per 1/60 s (1/60 to 1/960 s), the crosses
// also with Bullet's compound of convex pieces. Every point is one run timed and checked
// (bullet_runs.h runChecked and runBullet: the clock runs only while stepping, the one true-mesh
// checker at every 1/60 s instant between); further rounds re-time without the checker and the
// time is the median. Bullet gets the spawn list of voxfall's Lv 4, eq. 20, paper run.
// A voxfall series (one method and step rule) stops before a level whose run would take more
// than the cap of CPU seconds, predicted as 6 times the previous level's.
#include "tests/bench/frontier.h"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "render/figures/gnuplot.h"
#include "render/figures/paper_figures.h"
#include "tests/bench/bullet_runs.h"
#include "tests/bench/frontier_verdict.h"

namespace vf::bench {
namespace {

constexpr double kGoalRatio = 0.5;      // voxfall's time at most half of Bullet's
constexpr double kDepthFloorMm = 0.01;  // where depth 0 is drawn on the log axis
constexpr double kLevelCostFactor = 6;  // a level's run time over the previous level's

struct Options {
  int rounds = 1;
  double capSeconds = 30;
  std::vector<std::string> scenes{"cubes",    "crosses", "blocks",   "stack", "stack_10",
                                  "stack_20", "barrel",  "highpoly", "cliff"};
  std::string csvDir, figureBase;
};

// One point of the frontier.
struct Point {
  std::string scene, engine;  // engine: "voxfall", "bullet", "bullet_compound"
  std::string series;         // the line it belongs to: "paper eq. 20", ..., "Bullet"
  std::string setting;        // "Lv 4" or "1/240 s"
  double stepsPerSimSecond = 0;
  double ms = 0, mm = 0;      // CPU ms per simulated s (median), deepest interpenetration
  std::vector<double> times;  // s per simulated s, one per round
};

struct VoxfallSeries {
  const char* name;
  bool fast, clearance;
};
constexpr VoxfallSeries kSeries[] = {{"paper eq. 20", false, false},
                                     {"paper clearance", false, true},
                                     {"fast eq. 20", true, false},
                                     {"fast clearance", true, true}};
constexpr int kSubsteps[] = {1, 2, 4, 8, 16};

std::vector<std::string> split(const std::string& s) {
  std::vector<std::string> out;
  std::stringstream in(s);
  for (std::string item; std::getline(in, item, ',');)
    if (!item.empty()) out.push_back(item);
  return out;
}

Options parse(int argc, char** argv) {
  Options o;
  std::vector<std::string> positional;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    const bool hasValue = i + 1 < argc;
    if (a == "--rounds" && hasValue) {
      o.rounds = std::max(1, std::atoi(argv[++i]));
    } else if (a == "--cap" && hasValue) {
      o.capSeconds = std::atof(argv[++i]);
    } else if (a == "--scenes" && hasValue) {
      o.scenes = split(argv[++i]);
    } else if (a.rfind("--", 0) == 0) {
      throw std::runtime_error("--frontier: unknown option or missing value: " + a);
    } else {
      positional.push_back(a);
    }
  }
  if (positional.size() != 2 || o.scenes.empty())
    throw std::runtime_error(
        "usage: bullet_compare --frontier [--rounds N] [--scenes a,b] [--cap S] CSV_DIR "
        "FIGURE_BASE");
  o.csvDir = positional[0];
  o.figureBase = positional[1];
  return o;
}

// The CPU model (commas and quotes removed, as tests/bench/record_results.sh names machines)
// and the logical core count.
std::string machine() {
  std::string model = vf::fig::cpuModel();
  model.erase(
      std::remove_if(model.begin(), model.end(), [](char c) { return c == ',' || c == '"'; }),
      model.end());
  return model + " (" + std::to_string(std::thread::hardware_concurrency()) + " CPUs)";
}

Point point(const std::string& scene, const std::string& engine, const std::string& series,
            const std::string& setting) {
  Point p;
  p.scene = scene, p.engine = engine, p.series = series, p.setting = setting;
  return p;
}

void finish(Point& p, const Outcome& o, bool first) {
  if (first) p.stepsPerSimSecond = o.stepsPerSimSecond, p.mm = 1e3 * o.maxPenetration;
  p.times.push_back(o.cpuPerSimSecond);
  p.ms = 1e3 * median(p.times);
}

// The scene's points: round 0 timed and checked, later rounds timed only, interleaved.
std::vector<Point> runScene(const std::string& scene, const Options& o) {
  std::vector<Point> points;
  std::vector<vf::SceneSpec> specs;
  std::vector<std::vector<Spawn>> spawns;
  for (const VoxfallSeries& s : kSeries)
    for (int level = 2; level <= 6; ++level) {
      vf::SceneSpec spec = sceneAt(scene, level, s.fast, s.clearance);
      const bool reference = level == 4 && !s.fast && !s.clearance;  // Bullet's spawn list
      const Outcome out = runChecked(spec, true, reference ? &spawns : nullptr);
      Point p = point(scene, "voxfall", s.name, "Lv " + std::to_string(level));
      finish(p, out, true);
      points.push_back(p);
      specs.push_back(spec);
      std::fprintf(stderr, "  %s %s %s: %.1f ms/sim s, %.2f mm\n", scene.c_str(), s.name,
                   p.setting.c_str(), p.ms, p.mm);
      // The next level costs 4-7 times this one (the cubes, the paper's method): not run when
      // that would pass the cap.
      if (kLevelCostFactor * out.cpuPerSimSecond * spec.duration > o.capSeconds) break;
    }
  const vf::SceneSpec reference = sceneAt(scene, 4, false);
  if (spawns.empty()) runChecked(reference, false, &spawns);  // its level was over the cap
  const bool compoundToo = scene == "crosses";
  for (const bool compound : {false, true}) {
    if (compound && !compoundToo) continue;
    for (const int n : kSubsteps) {
      Point p =
          point(scene, compound ? "bullet_compound" : "bullet",
                compound ? "Bullet compound" : "Bullet", "1/" + std::to_string(60 * n) + " s");
      finish(p, runBullet(reference, spawns, true, compound, n), true);
      points.push_back(p);
      std::fprintf(stderr, "  %s %s %s: %.1f ms/sim s, %.2f mm\n", scene.c_str(), p.series.c_str(),
                   p.setting.c_str(), p.ms, p.mm);
    }
  }
  for (int r = 1; r < o.rounds; ++r) {
    std::size_t i = 0;
    for (; i < specs.size(); ++i) finish(points[i], runVoxfall(specs[i], false, nullptr), false);
    for (; i < points.size(); ++i) {
      const int n = kSubsteps[(i - specs.size()) % std::size(kSubsteps)];
      finish(points[i], runBullet(reference, spawns, false, points[i].engine != "bullet", n),
             false);
    }
  }
  return points;
}

std::vector<FrontierPoint> frontierOf(const std::vector<Point>& points, const std::string& scene,
                                      const std::string& engine) {
  std::vector<FrontierPoint> out;
  for (const Point& p : points)
    if (p.scene == scene && p.engine == engine)
      out.push_back({p.engine == "voxfall" ? p.setting + " " + p.series : p.setting, p.ms, p.mm});
  return out;
}

struct SceneVerdict {
  std::string scene, bullet;  // bullet: "bullet" or "bullet_compound"
  std::vector<PointVerdict> points;
};

std::vector<SceneVerdict> verdicts(const std::vector<Point>& points, const Options& o) {
  std::vector<SceneVerdict> out;
  for (const std::string& scene : o.scenes)
    for (const char* engine : {"bullet", "bullet_compound"}) {
      const std::vector<FrontierPoint> bullet = frontierOf(points, scene, engine);
      if (bullet.empty()) continue;
      out.push_back({scene, engine,
                     frontierVerdict(frontierOf(points, scene, "voxfall"), bullet, kGoalRatio)});
    }
  return out;
}

std::ofstream openCsv(const std::string& path) {
  std::ofstream f(path);
  if (!f) throw std::runtime_error(path + ": cannot write");
  return f;
}

std::string num(const char* format, double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, format, v);
  return buf;
}

void writeCsvs(const std::vector<Point>& points, const std::vector<SceneVerdict>& all,
               const Options& o) {
  const std::string lead =
      "\"" + machine() + "\",\"" + bulletVersion() + "\"," + std::to_string(o.rounds) + ",";
  std::ofstream f = openCsv(o.csvDir + "/bullet_frontier.csv");
  f << "machine,bullet_version,rounds,scene,engine,series,setting,steps_per_sim_s,"
       "cpu_ms_per_sim_s,deepest_mm\n";
  for (const Point& p : points)
    f << lead << p.scene << "," << p.engine << "," << p.series << "," << p.setting << ","
      << num("%.0f", p.stepsPerSimSecond) << "," << num("%.3f", p.ms) << "," << num("%.2f", p.mm)
      << "\n";
  std::ofstream v = openCsv(o.csvDir + "/bullet_frontier_verdict.csv");
  v << "machine,bullet_version,rounds,scene,bullet,bullet_step,bullet_ms_per_sim_s,"
       "bullet_deepest_mm,voxfall_setting,voxfall_ms_per_sim_s,voxfall_deepest_mm,"
       "voxfall_over_bullet,pass\n";
  for (const SceneVerdict& s : all)
    for (const PointVerdict& p : s.points)
      v << lead << s.scene << "," << s.bullet << "," << p.bullet.setting << ","
        << num("%.3f", p.bullet.msPerSimSecond) << "," << num("%.2f", p.bullet.deepestMm) << ","
        << (p.matched ? "\"" + p.voxfall.setting + "\"" : std::string("none")) << ","
        << (p.matched ? num("%.3f", p.voxfall.msPerSimSecond) : "") << ","
        << (p.matched ? num("%.2f", p.voxfall.deepestMm) : "") << ","
        << (p.matched ? num("%.3f", p.ratio) : "") << "," << (p.pass ? "yes" : "no") << "\n";
}

void printMarkdown(const std::vector<SceneVerdict>& all) {
  std::printf(
      "| scene | Bullet | goal met | Bullet points failing: step (ms, mm) -> voxfall's cheapest "
      "as deep (ms, mm, ratio) |\n|---|---|---|---|\n");
  for (const SceneVerdict& s : all) {
    std::string failing;
    for (const PointVerdict& p : s.points) {
      if (p.pass) continue;
      failing +=
          (failing.empty() ? "" : "; ") + p.bullet.setting + " (" +
          num("%.2f", p.bullet.msPerSimSecond) + ", " + num("%.1f", p.bullet.deepestMm) + ") -> " +
          (p.matched ? p.voxfall.setting + " (" + num("%.2f", p.voxfall.msPerSimSecond) + ", " +
                           num("%.1f", p.voxfall.deepestMm) + ", " + num("%.2f", p.ratio) + "x)"
                     : std::string("none as shallow"));
    }
    std::printf("| %s | %s | %s | %s |\n", s.scene.c_str(),
                s.bullet == "bullet" ? "hull/GImpact" : "compound",
                goalMet(s.points) ? "yes" : "no", failing.empty() ? "-" : failing.c_str());
  }
}

// The figure: one panel per scene, time against depth on log axes, a line per series.
struct Group {
  std::string series;
  int color;
};
constexpr const char* kGoalSeries = "half Bullet's time";

std::vector<Group> groups() {
  return {{"paper eq. 20", 0},   {"paper clearance", 5}, {"fast eq. 20", 1},
          {"fast clearance", 4}, {"Bullet", 6},          {"Bullet compound", 3}};
}

// Writes the group's points of `scene` to a data file; false if it has none. `clean`: some
// point is no deeper than the interpenetration threshold.
bool writeGroup(const std::vector<Point>& points, const std::string& scene,
                const std::string& series, const std::string& path, bool* clean) {
  std::ofstream f(path);
  f << "depth_drawn_mm,ms,clean\n";
  bool any = false;
  *clean = false;
  for (const Point& p : points) {
    if (p.scene != scene || p.series != series) continue;
    const bool ok = p.mm <= 1e3 * vf::fig::kInterpenetrationThreshold;
    f << std::max(p.mm, kDepthFloorMm) << "," << p.ms << "," << (ok ? 1 : 0) << "\n";
    any = true;
    *clean |= ok;
  }
  if (!f) throw std::runtime_error(path + ": cannot write");
  return any;
}

vf::fig::Panel scenePanel(const std::vector<Point>& points, const std::string& scene,
                          const vf::fig::ScratchFolder& scratch, bool legend) {
  vf::fig::Panel panel;
  panel.title = scene;
  panel.xLabel = "deepest interpenetration (mm)";
  panel.yLabel = "CPU ms per simulated s";
  panel.logX = panel.logY = true;
  panel.settings = {legend ? "set key bottom left font ',8' samplen 2" : "unset key",
                    "set xrange [" + num("%g", 0.5 * kDepthFloorMm) + ":*]", "set format x '%g'",
                    "set format y '%g'"};
  for (const Group& g : groups()) {
    bool clean = false;
    const std::string file = scratch.file(scene + "_" + std::to_string(g.color) + ".csv");
    if (!writeGroup(points, scene, g.series, file, &clean)) continue;
    panel.series.push_back({"", file, "1:2", "lines", g.color});
    panel.series.push_back({"", file, "1:2", "points", g.color, true});
    if (clean) panel.series.push_back({"", file, "1:($3 > 0 ? $2 : 1/0)", "points", g.color});
    if (g.series.rfind("Bullet", 0) == 0)
      panel.series.push_back({"", file, "1:($2 * " + num("%g", kGoalRatio) + ")", "lines", 2});
  }
  if (legend) {
    for (const Group& g : groups())
      panel.series.push_back({g.series, "", "", "linespoints", g.color, false, true});
    panel.series.push_back({kGoalSeries, "", "", "lines", 2, false, true});
  }
  return panel;
}

void drawFrontier(const std::vector<Point>& points, const std::vector<std::string>& scenes,
                  const std::string& footnote, const std::string& base) {
  const vf::fig::ScratchFolder scratch;
  vf::fig::Figure figure;
  figure.title = "Accuracy against cost: voxfall Lv 2-6 and Bullet 1/60-1/960 s steps";
  figure.footnote = footnote;
  for (std::size_t i = 0; i < scenes.size(); ++i)
    figure.panels.push_back(scenePanel(points, scenes[i], scratch, i == 0));
  figure.rows = static_cast<int>((scenes.size() + 2) / 3);
  figure.width = 1500;
  figure.height = 60 + 420 * figure.rows;
  vf::fig::drawFigure(figure, base);
}

}  // namespace

int frontierMain(int argc, char** argv) {
  const Options o = parse(argc, argv);
  std::vector<Point> points;
  for (const std::string& scene : o.scenes) {
    std::fprintf(stderr, "frontier: %s\n", scene.c_str());
    for (const Point& p : runScene(scene, o)) points.push_back(p);
  }
  const std::vector<SceneVerdict> all = verdicts(points, o);
  writeCsvs(points, all, o);
  printMarkdown(all);
  const std::string footnote =
      "CPU ms of stepping per simulated s (" +
      (o.rounds == 1 ? std::string("one round")
                     : "median of " + std::to_string(o.rounds) + " rounds") +
      "); depth: deepest true-mesh interpenetration at any 1/60 s instant, one checker for "
      "both; depth 0 drawn at " +
      num("%.2f", kDepthFloorMm) + " mm; hollow: deeper than " +
      num("%.0f", 1e3 * vf::fig::kInterpenetrationThreshold) + " mm. Machine: " + machine() + ".";
  drawFrontier(points, o.scenes, footnote, o.figureBase);
  return 0;
}

}  // namespace vf::bench

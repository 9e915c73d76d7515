// The comparison figures (figs. 13, 14 and 16; digest sections 7-8): the voxel method at its
// levels against the polygon method at the paper's steps, one row per configuration, as a CSV,
// a bar or point chart with hollow markers for interpenetrating runs, and a README section.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <functional>
#include <sstream>

#include "render/figures/figure_runs.h"
#include "render/figures/gnuplot.h"
#include "sim/core/error.h"

namespace vf::fig {
namespace {

namespace fs = std::filesystem;

std::string methodName(const RunConfig& c) {
  return c.collider == ColliderMethod::kPolygon ? "polygon" : "voxel";
}

// CSV columns (1-based for gnuplot): 1 slot, 2 label, 3 method, 4 level, 5 step_s, 6 blocks,
// 7 compute_s, 8 compute_s if no interpenetration (else empty), 9 repeats, 10 steps,
// 11 max_penetration_body_body_m, 12 max_penetration_body_ground_m, 13 interpenetrated,
// 14 overlapping_releases.
std::string comparisonCsv(const std::vector<Comparison>& rows) {
  std::ostringstream o;
  o << "slot,label,method,level,step_s,blocks,compute_s,compute_s_clean,repeats,steps,"
       "max_penetration_body_body_m,max_penetration_body_ground_m,interpenetrated,overlapping_"
       "releases\n";
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const Comparison& c = rows[i];
    const RunResult& r = c.result;
    VF_ASSERT(c.label.find(',') == std::string::npos);  // plain CSV field
    o << i << "," << c.label << "," << methodName(c.config) << ","
      << (c.config.collider == ColliderMethod::kVoxel ? std::to_string(c.config.level) : "") << ","
      << fmt("%.9g", c.config.step > 0 ? c.config.step : r.meanStep) << "," << c.blocks << ","
      << fmt("%.6g", r.seconds) << ","
      << (r.interpenetrated() ? std::string() : fmt("%.6g", r.seconds)) << "," << r.samples.size()
      << "," << r.steps << "," << fmt("%.6g", r.penetrationBodyBody) << ","
      << fmt("%.6g", r.penetrationBodyGround) << "," << (r.interpenetrated() ? 1 : 0) << ","
      << r.overlappingReleases << "\n";
  }
  return o.str();
}

std::string comparisonTable(const std::vector<Comparison>& rows,
                            const std::function<std::string(const Comparison&)>& paper) {
  std::ostringstream o;
  o << "| run | compute time (s) | steps | max overlap body-body / body-ground (mm) | "
       "interpenetrated (> "
    << mm(kInterpenetrationThreshold) << " mm) | paper |\n|---|---|---|---|---|---|\n";
  for (const Comparison& c : rows) {
    const RunResult& r = c.result;
    o << "| " << c.label << (c.blocks ? ", " + std::to_string(c.blocks) + " blocks" : "") << " | "
      << fmt("%.3f", r.seconds) << " | " << r.steps << " | " << mm(r.penetrationBodyBody) << " / "
      << mm(r.penetrationBodyGround) << " | " << (r.interpenetrated() ? "yes" : "no")
      << (r.overlappingReleases
              ? " (" + std::to_string(r.overlappingReleases) + " released into another body)"
              : std::string())
      << " | " << paper(c) << " |\n";
  }
  return o.str();
}

// The row labelled `label` (and, for fig. 16, with `blocks` blocks), or null.
const Comparison* findRow(const std::vector<Comparison>& rows, const std::string& label,
                          int blocks = 0) {
  for (const Comparison& c : rows)
    if (c.label == label && c.blocks == blocks) return &c;
  return nullptr;
}

// "polygon at 1/2400 takes 0.95 times the time of Lv 4 at 1/120", or "" if a row is missing.
std::string timeRatio(const Comparison* a, const Comparison* b) {
  if (!a || !b || b->result.seconds <= 0) return "";
  return a->label + " takes " + fmt("%.2g", a->result.seconds / b->result.seconds) +
         " times the time of " + b->label;
}

// The non-empty parts joined by "; " and closed by ".", or "".
std::string sentence(const std::vector<std::string>& parts) {
  std::string out;
  for (const std::string& p : parts)
    if (!p.empty()) out += (out.empty() ? "" : "; ") + p;
  return out.empty() ? out : out + ".";
}

// Which runs interpenetrated, from the data.
std::string interpenetrationFindings(const std::vector<Comparison>& rows) {
  std::string bad, good;
  for (const Comparison& c : rows) {
    std::string& list = c.result.interpenetrated() ? bad : good;
    const std::string name = c.label + (c.blocks ? " (" + std::to_string(c.blocks) + ")" : "");
    list += (list.empty() ? "" : ", ") + name;
  }
  return "interpenetrated: " + (bad.empty() ? std::string("none") : bad) +
         "; clean: " + (good.empty() ? std::string("none") : good) + ".";
}

// Bars (linear axis) or points (log axis) per configuration, voxel and polygon in two colours,
// hollow where the run interpenetrated.
Panel comparisonPanel(const std::string& title, const std::string& csv,
                      const std::vector<Comparison>& rows, bool logY) {
  Panel p;
  p.title = title;
  p.xLabel = "";
  p.yLabel = "compute time (s)";
  p.logY = logY;
  // Tick labels on two lines: "Lv 2" over "1/120".
  std::string tics = "set xtics (";
  for (std::size_t i = 0; i < rows.size(); ++i) {
    std::string label = rows[i].label;
    label.replace(label.find(" at "), 4, "\\n");
    tics += (i ? ", " : "") + std::string("\"") + label + "\" " + std::to_string(i);
  }
  p.settings = {tics + ")", "set xrange [-0.7:" + std::to_string(rows.size()) + "-0.3]",
                logY ? "set yrange [*:*]" : "set yrange [0:*]", "set key top left"};
  const std::string style = logY ? "points" : "boxes";
  for (const auto& [method, color] : {std::pair{"voxel", 0}, std::pair{"polygon", 1}}) {
    const std::string is = "strcol(3) eq \"" + std::string(method) + "\"";
    // gnuplot refuses a series without a single defined point: add only those with one.
    bool any = false, anyClean = false;
    for (const Comparison& c : rows)
      if (methodName(c.config) == method) any = true, anyClean |= !c.result.interpenetrated();
    if (!any) continue;
    // Every run hollow, the clean ones filled over them; the legend shows the method filled.
    p.series.push_back({"", csv, "1:(" + is + " ? $7 : NaN)", style, color, true});
    if (anyClean) p.series.push_back({"", csv, "1:(" + is + " ? $8 : NaN)", style, color, false});
    p.series.push_back({std::string(method) + " method", "", "", style, color, false, true});
  }
  return p;
}

void runAll(const PaperFigureOptions& o, const std::string& tag, double duration,
            std::vector<Comparison>& rows, RunProgress& progress) {
  for (Comparison& c : rows) {
    c.result = runScene(o.scenesDir, c.config);
    progress.done(tag + " " + c.config.scene + " " + c.label, expectedWork(c.config, duration),
                  c.result);
  }
}

// Runs a comparison's rows and writes OUT/TAG.csv, .png and .svg as bars (or, on a log axis,
// points) per row.
void runAndDraw(const PaperFigureOptions& o, const std::string& tag, double duration,
                const std::string& title, const std::string& panelTitle, bool logY, int repeats,
                std::vector<Comparison>& rows, RunProgress& progress) {
  runAll(o, tag, duration, rows, progress);
  const std::string base = (fs::path(o.outDir) / tag).string();
  writeText(base + ".csv", comparisonCsv(rows));
  Figure f;
  f.title = title;
  f.footnote = footnote(repeats, true);
  f.panels = {comparisonPanel(panelTitle, base + ".csv", rows, logY)};
  f.height = 520;
  drawFigure(f, base);
}

Comparison voxelRun(const std::string& scene, int level, double step, int repeats) {
  return {"Lv " + std::to_string(level) + " at " + stepText(step),
          {scene, level, step, ColliderMethod::kVoxel, repeats},
          0,
          {}};
}
Comparison polygonRun(const std::string& scene, double step, int repeats) {
  // The tree level only matters for eq. 20, which the polygon runs never use (fixed steps).
  return {
      "polygon at " + stepText(step), {scene, 4, step, ColliderMethod::kPolygon, repeats}, 0, {}};
}

// "3.1 times": how much a configuration's time grows from 10 to 30 blocks ("?" if missing).
std::string growth(const std::vector<Comparison>& rows, const std::string& label) {
  const Comparison *a = findRow(rows, label, 10), *b = findRow(rows, label, 30);
  if (!a || !b || a->result.seconds <= 0) return "?";
  return fmt("%.2g", b->result.seconds / a->result.seconds) + " times";
}

}  // namespace

std::vector<Comparison> figure13Rows(bool quick, int repeats) {
  std::vector<Comparison> rows;
  for (int lv : {2, 3, 4}) rows.push_back(voxelRun("blocks", lv, 1.0 / 120, repeats));
  rows.push_back(voxelRun("blocks", 4, 0, repeats));  // eq. 20 as voxfall computes it
  const std::vector<int> steps = quick ? std::vector<int>{120, 600, 2400}
                                       : std::vector<int>{120, 240, 480, 960, 1440, 1920, 2400};
  for (int n : steps) rows.push_back(polygonRun("blocks", 1.0 / n, repeats));
  return rows;
}

Section figure13(const PaperFigureOptions& o, int repeats, RunProgress& progress) {
  std::vector<Comparison> rows = figure13Rows(o.quick, repeats);
  runAndDraw(o, "fig13", 5.0, "Fig. 13: example 2 (10 blocks of 12 triangles), compute time",
             "voxel levels and eq. 20 against the polygon method", false, repeats, rows, progress);
  auto paper = [](const Comparison& c) -> std::string {
    if (c.config.collider == ColliderMethod::kVoxel)
      return c.config.step > 0 ? "no interpenetration at 1/120" : "(not run: the paper used 1/120)";
    return std::lround(1 / c.config.step) >= 2400 ? "first step without interpenetration"
                                                  : "interpenetrated";
  };
  std::ostringstream md;
  md << "## Fig. 13: example 2, compute time of the two methods\n\n"
     << "`fig13.png`, `fig13.svg`, data `fig13.csv`. Scene `blocks.toml` (10 blocks of 12 "
        "triangles, 5 s). Hollow bars: runs whose true meshes interpenetrated.\n\n"
     << comparisonTable(rows, paper) << "\n"
     << "- Paper: voxel level 4 at 1/120 s does not interpenetrate; the polygon method "
        "interpenetrates at every step down to 1/1920 s and is clean only at 1/2400 s, where it "
        "costs more than the voxel method at 1/120 s.\n"
     << "- Why ours can differ: (1) the paper's 1/120 s comes from eq. 20 with the throw speed "
        "(2 m/s gives 1/113 s); a block lands at about 4.9 m/s, where eq. 20 at level 4 asks for "
        "about 1/300 s, so at a fixed 1/120 s a landing block can sink into the floor by more "
        "than a leaf sphere's radius. The row \"Lv 4, eq. 20\" runs voxfall's per-step eq. 20. "
        "(2) In C++ a 12-triangle SAT test is cheap (a few hundred feature tests per pair) "
        "while a level-4 sphere-tree descent tests thousands of spheres, so for these simple "
        "blocks the polygon method is not slower per step; the paper's MATLAB timings reflect "
        "its own implementation's costs. (3) The pile can build up back under the release "
        "point; the scene raises a release that would be born inside a block just clear of it "
        "(`clear_release`) and leaves every other throw at 1 m, so the overlaps are the "
        "methods'.\n"
     << "- Ours: " << interpenetrationFindings(rows) << " "
     << timeRatio(findRow(rows, "polygon at 1/2400"), findRow(rows, "Lv 4 at 1/120")) << "; "
     << timeRatio(findRow(rows, "polygon at 1/2400"), findRow(rows, "Lv 4 at eq. 20")) << ".\n\n";
  return {"fig13", md.str()};
}

std::vector<Comparison> figure14Rows(bool quick, int repeats) {
  std::vector<Comparison> rows;
  for (int lv : quick ? std::vector<int>{2, 3} : std::vector<int>{2, 3, 4})
    rows.push_back(voxelRun("highpoly", lv, 1.0 / 120, repeats));
  for (int n : quick ? std::vector<int>{120} : std::vector<int>{120, 600})
    rows.push_back(polygonRun("highpoly", 1.0 / n, repeats));
  return rows;
}

Section figure14(const PaperFigureOptions& o, int repeats, RunProgress& progress) {
  std::vector<Comparison> rows = figure14Rows(o.quick, repeats);
  runAndDraw(o, "fig14", 6.0,
             "Fig. 14: example 3 (blocks of 192 triangles), compute time, log scale",
             "voxel levels against the polygon method", true, repeats, rows, progress);
  auto paper = [](const Comparison& c) -> std::string {
    return c.config.collider == ColliderMethod::kVoxel
               ? (c.config.level == 4 ? "used: 1/120 s, no jitter" : "-")
               : "far slower than the voxel method";
  };
  std::ostringstream md;
  md << "## Fig. 14: example 3, the same comparison on 192-triangle blocks\n\n"
     << "`fig14.png`, `fig14.svg` (log time axis), data `fig14.csv`. Scene `highpoly.toml`.\n\n"
     << comparisonTable(rows, paper) << "\n"
     << "- Paper: with 192 triangles per block the polygon method is far slower than the voxel "
        "method at 1/120 and 1/600 s (log axis).\n"
     << "- Agrees: the polygon method's cost grows with the polygon count (every triangle "
        "against every vertex, every edge against every edge: about 16x the triangles of "
        "example 2 cost about 100x the feature tests per pair), while the sphere tree's cost "
        "depends on the level, not the triangles.\n"
     << "- Ours: " << interpenetrationFindings(rows) << " "
     << sentence({timeRatio(findRow(rows, "polygon at 1/120"), findRow(rows, "Lv 4 at 1/120")),
                  timeRatio(findRow(rows, "polygon at 1/600"), findRow(rows, "Lv 4 at 1/120"))})
     << " The scene starts every block clear of the others' leaf spheres at every level run "
        "here (the two on the floor 0.6 m apart, the throws from 3 m back), so the overlaps "
        "measured are the method's.\n\n";
  return {"fig14", md.str()};
}

std::vector<Comparison> figure16Rows(bool quick, int repeats) {
  std::vector<Comparison> rows;
  const std::vector<std::pair<int, std::string>> counts =
      quick ? std::vector<std::pair<int, std::string>>{{10, "stack_10"}}
            : std::vector<std::pair<int, std::string>>{
                  {10, "stack_10"}, {20, "stack_20"}, {30, "stack"}};
  // Grouped by configuration so that each curve's rows are consecutive in the CSV.
  for (int n : {0, 600, 1200})
    for (const auto& [blocks, scene] : counts) {
      Comparison c =
          n == 0 ? voxelRun(scene, 4, 1.0 / 150, repeats) : polygonRun(scene, 1.0 / n, repeats);
      c.blocks = blocks;
      rows.push_back(c);
    }
  return rows;
}

Section figure16(const PaperFigureOptions& o, int repeats, RunProgress& progress) {
  std::vector<Comparison> rows = figure16Rows(o.quick, repeats);
  runAll(o, "fig16", 12.0, rows, progress);
  const std::string base = (fs::path(o.outDir) / "fig16").string();
  writeText(base + ".csv", comparisonCsv(rows));
  Figure f;
  f.title = "Fig. 16: example 4 (stacking), compute time against the number of blocks";
  f.footnote = footnote(repeats, true);
  Panel p{"",
          "blocks dropped",
          "compute time (s)",
          false,
          false,
          {},
          {"set xtics 10", "set xrange [5:35]", "set yrange [0:*]", "set key bottom right"}};
  int color = 0;
  for (const std::string& label : {std::string("Lv 4 at 1/150"), std::string("polygon at 1/600"),
                                   std::string("polygon at 1/1200")}) {
    const std::string is = "strcol(2) eq \"" + label + "\"";
    // Every run hollow, the clean ones filled over them; the legend shows the series filled.
    p.series.push_back(
        {"", base + ".csv", "6:(" + is + " ? $7 : NaN)", "linespoints", color, true});
    p.series.push_back({label, "", "", "linespoints", color, false, true});
    // gnuplot refuses a series without a single defined point.
    if (std::any_of(rows.begin(), rows.end(), [&](const Comparison& c) {
          return c.label == label && !c.result.interpenetrated();
        }))
      p.series.push_back({"", base + ".csv", "6:(" + is + " ? $8 : NaN)", "points", color, false});
    ++color;
  }
  f.panels = {p};
  drawFigure(f, base);
  auto paper = [](const Comparison& c) -> std::string {
    return c.config.collider == ColliderMethod::kVoxel ? "no interpenetration; grows slowly"
                                                       : "interpenetrated (every count)";
  };
  std::ostringstream md;
  md << "## Fig. 16: example 4, compute time against the number of blocks\n\n"
     << "`fig16.png`, `fig16.svg`, data `fig16.csv`. Scenes `stack_10.toml`, `stack_20.toml`, "
        "`stack.toml` (30 blocks).\n\n"
     << comparisonTable(rows, paper) << "\n"
     << "- Paper: the voxel method at level 4 and 1/150 s never interpenetrates and its time "
        "grows slowly with the block count; the polygon method interpenetrates at 1/600 and "
        "1/1200 s for every count while costing more.\n"
     << "- Ours: " << interpenetrationFindings(rows)
     << " From 10 to 30 blocks: " << growth(rows, "Lv 4 at 1/150") << " (voxel), "
     << growth(rows, "polygon at 1/600") << " (polygon at 1/600), "
     << growth(rows, "polygon at 1/1200") << " (polygon at 1/1200).\n"
     << "- Our polygon method resolves a contact when it is found, with the same "
        "sequential-impulse solver and warm starting as the voxel method; how deep blocks sink "
        "depends on how far they move per step, so a smaller step shrinks the overlap, and "
        "with the threshold printed here 1/1200 s can pass where the paper saw "
        "interpenetration (the paper judged by eye).\n\n";
  return {"fig16", md.str()};
}

}  // namespace vf::fig

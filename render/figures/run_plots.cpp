#include "render/figures/run_plots.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>

#include "render/figures/gnuplot.h"
#include "render/output/number_text.h"
#include "render/output/output_file.h"
#include "sim/core/error.h"

namespace vf::fig {
namespace {

namespace fs = std::filesystem;

struct Row {
  int frame = 0;
  double time = 0;
  int body = 0;
  Vec3 x, v, w;
  Quat q;
};

constexpr const char* kHeader = "frame,time,body,x,y,z,qw,qx,qy,qz,vx,vy,vz,wx,wy,wz";

std::vector<Row> readRun(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path, "cannot read the run CSV");
  std::string line;
  if (!std::getline(in, line) || line != kHeader)
    throw InputError(sourceLocation(path, 1),
                     std::string("not a voxfall run CSV: the first line must be ") + kHeader);
  std::vector<Row> rows;
  for (int n = 2; std::getline(in, line); ++n) {
    if (line.empty()) continue;
    double f[16];
    std::stringstream s(line);
    std::string item;
    int k = 0;
    for (; k < 16 && std::getline(s, item, ','); ++k) {
      char* end = nullptr;
      f[k] = std::strtod(item.c_str(), &end);
      if (item.empty() || *end != '\0' || !std::isfinite(f[k]))
        throw InputError(sourceLocation(path, n), "field " + std::to_string(k + 1) + " '" + item +
                                                      "' is not a finite number");
    }
    if (k != 16 || std::getline(s, item, ','))
      throw InputError(sourceLocation(path, n),
                       "expected 16 fields (" + std::string(kHeader) + ")");
    // The frame and the body id are counts: whole numbers in int's range (a cast of one past
    // it would be undefined).
    for (const int col : {0, 2})
      if (!(f[col] >= 0 && f[col] <= std::numeric_limits<int>::max() &&
            f[col] == std::floor(f[col]))) {
        char got[64];
        std::snprintf(got, sizeof got, "%.17g", f[col]);
        throw InputError(sourceLocation(path, n),
                         std::string(col == 0 ? "the frame" : "the body id") +
                             " must be a whole number from 0 to " +
                             std::to_string(std::numeric_limits<int>::max()) + ", got " + got);
      }
    Row r;
    r.frame = static_cast<int>(f[0]);
    r.time = f[1];
    r.body = static_cast<int>(f[2]);
    r.x = Vec3(f[3], f[4], f[5]);
    r.q = Quat(f[6], f[7], f[8], f[9]);
    r.v = Vec3(f[10], f[11], f[12]);
    r.w = Vec3(f[13], f[14], f[15]);
    rows.push_back(r);
  }
  if (rows.empty()) throw InputError(path, "the run CSV has no rows");
  return rows;
}

void writeText(const std::string& path, const std::string& text) {
  // Figures and plots rewrite their own output folder, as reports do.
  OutputFile out(path, replaceOutputs());
  std::fputs(text.c_str(), out.stream());
  out.commit();
}

// Where plotRun writes: two CSVs and three figures (each + .png and .svg).
struct PlotFiles {
  std::string energyCsv, bodiesCsv;
  std::string energyBase, speedBase, tracksBase;
};

PlotFiles plotFiles(const std::string& outDir) {
  const fs::path dir(outDir);
  return {(dir / "energy.csv").string(), (dir / "bodies.csv").string(), (dir / "energy").string(),
          (dir / "speed").string(), (dir / "trajectories").string()};
}

// The energies per frame (energy.csv) and each body's speed and centre over time (bodies.csv),
// from the run's rows. Without `o.bodies` every body counts as 1 kg, translation only.
void writeRunTables(const std::vector<Row>& rows, const RunPlotOptions& o, const PlotFiles& files) {
  const bool perKg = o.bodies.empty();
  // Energies per frame, in frame order (rows of one frame are consecutive).
  std::ostringstream energy;
  energy << "frame,time_s,kinetic_J,potential_J,total_J\n";
  std::map<int, std::string> perBodyRows;  // body -> its rows, so each curve is consecutive
  auto flush = [&](int frame, double time, double ke, double pe) {
    energy << csvRow(frame, time, ke, pe, ke + pe);
  };
  int frame = rows[0].frame;
  double time = rows[0].time, ke = 0, pe = 0;
  for (const Row& r : rows) {
    if (r.frame != frame) {
      flush(frame, time, ke, pe);
      frame = r.frame, time = r.time, ke = 0, pe = 0;
    }
    const BodyMass m = perKg ? BodyMass{} : o.bodies[r.body];
    const Mat3 R = r.q.normalized().toRotationMatrix();
    ke += 0.5 * m.mass * r.v.squaredNorm() + 0.5 * r.w.dot(R * m.inertiaBody * R.transpose() * r.w);
    pe -= m.mass * o.gravity.dot(r.x);
    perBodyRows[r.body] += csvRow(r.body, r.time, r.v.norm(), r.x.x(), r.x.y(), r.x.z());
  }
  flush(frame, time, ke, pe);
  std::string bodies = "body,time_s,speed_m_s,x_m,y_m,z_m\n";
  for (const auto& [id, text] : perBodyRows) bodies += text;

  writeText(files.energyCsv, energy.str());
  writeText(files.bodiesCsv, bodies);
}

// One series per body 0..maxBody of `csv`, plotting `xy` ("$x:$y") where column `bodyColumn`
// is that body; named in the key only with fewer than ten bodies.
std::vector<Series> perBodySeries(const std::string& csv, const std::string& xy, int bodyColumn,
                                  const std::string& style, int maxBody) {
  const bool legend = maxBody < 10;
  std::vector<Series> s;
  for (int b = 0; b <= maxBody; ++b)
    s.push_back({legend ? "body " + std::to_string(b) : "", csv,
                 "(column(" + std::to_string(bodyColumn) + ") == " + std::to_string(b) + " ? " +
                     xy.substr(0, xy.find(':')) + " : NaN):(" + xy.substr(xy.find(':') + 1) + ")",
                 style, b, false});
  return s;
}

// The three figures: energy over time, each body's speed, and the centres' paths in plan and
// side view.
void drawRunFigures(const RunPlotOptions& o, const PlotFiles& files, int maxBody,
                    const std::string& note, bool perKg) {
  const std::string unit = perKg ? "energy per kg, translation only (J/kg)" : "energy (J)";
  Figure e;
  e.title = o.title + ": energy";
  e.footnote = note;
  e.panels = {{"",
               "time (s)",
               unit,
               false,
               false,
               {{"kinetic", files.energyCsv, "2:3", "lines", 0, false},
                {"potential", files.energyCsv, "2:4", "lines", 1, false},
                {"total", files.energyCsv, "2:5", "lines", 6, false}},
               {"set key top right"}}};
  drawFigure(e, files.energyBase);

  const bool legend = maxBody < 10;
  const std::string& csv = files.bodiesCsv;
  Figure v;
  v.title = o.title + ": speed of each body";
  v.footnote = note;
  v.panels = {{"",
               "time (s)",
               "speed (m/s)",
               false,
               false,
               perBodySeries(csv, "$2:$3", 1, "lines", maxBody),
               {legend ? "set key top right" : "unset key"}}};
  drawFigure(v, files.speedBase);

  Figure t;
  t.title = o.title + ": trajectories of the centres of mass";
  t.footnote = note;
  t.panels = {{"plan view",
               "x (m)",
               "y (m)",
               false,
               false,
               perBodySeries(csv, "$4:$5", 1, "lines", maxBody),
               {"set size ratio -1", legend ? "set key top left" : "unset key"}},
              {"side view",
               "x (m)",
               "z (m)",
               false,
               false,
               perBodySeries(csv, "$4:$6", 1, "lines", maxBody),
               {"set size ratio -1", "unset key"}}};
  t.width = 1200;
  drawFigure(t, files.tracksBase);
}

}  // namespace

void plotRun(const std::string& runCsv, const RunPlotOptions& o) {
  const PlotFiles files = plotFiles(o.outDir);
  OutputRules rules = replaceOutputs();
  rules.inputs = o.inputs;
  rules.inputs.push_back(runCsv);
  for (const std::string& path : {files.energyCsv, files.bodiesCsv})  // before anything is written
    checkOutputPath(path, rules);
  for (const std::string& base : {files.energyBase, files.speedBase, files.tracksBase}) {
    checkOutputPath(base + ".png", rules);
    checkOutputPath(base + ".svg", rules);
  }
  const std::vector<Row> rows = readRun(runCsv);
  std::error_code ec;
  fs::create_directories(o.outDir, ec);
  if (ec) throw InputError(o.outDir, "cannot create the output folder: " + ec.message());
  const bool perKg = o.bodies.empty();
  int maxBody = 0;
  for (const Row& r : rows) maxBody = std::max(maxBody, r.body);
  if (!perKg && maxBody >= static_cast<int>(o.bodies.size()))
    throw InputError(runCsv, "body " + std::to_string(maxBody) + " is not in the scene (" +
                                 std::to_string(o.bodies.size()) + " bodies)");
  writeRunTables(rows, o, files);
  const std::string note = "from " + fs::path(runCsv).filename().string() +
                           (perKg ? "; no scene given: every body counts as 1 kg" : "");
  drawRunFigures(o, files, maxBody, note, perKg);
}

}  // namespace vf::fig

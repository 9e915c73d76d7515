// The ensemble's tables and summary (see ensemble_output.h).
#include "render/run/ensemble_output.h"

#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>
#include <string>

#include "render/output/number_text.h"
#include "render/output/output_file.h"
#include "sim/core/error.h"
#include "sim/ensemble/ensemble_shards.h"
#include "sim/recorder.h"

namespace vf {
namespace {

// A number in `format`, or nothing (an empty CSV field) when it is not finite.
std::string fmt(const char* format, double v) {
  if (!std::isfinite(v)) return "";
  char buf[64];
  std::snprintf(buf, sizeof buf, format, v);
  return buf;
}

// JSON numbers: non-finite ones become null.
nlohmann::json number(double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(); }

// Sorted copy, for the summary's percentiles.
std::vector<double> sorted(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v;
}

nlohmann::ordered_json distribution(const std::vector<double>& values) {
  const std::vector<double> s = sorted(values);
  if (s.empty()) return nlohmann::ordered_json();
  nlohmann::ordered_json j;
  j["min"] = number(s.front());
  j["p50"] = number(nearestRankPercentile(s.data(), s.size(), 50));
  j["p95"] = number(nearestRankPercentile(s.data(), s.size(), 95));
  j["max"] = number(s.back());
  return j;
}

}  // namespace

// runs.csv: one row per realisation; coordinates in the DEM file's own coordinates.
void writeRunsCsv(std::FILE* f, const Ensemble& ens, const std::vector<RealisationResult>& runs) {
  const Heightfield& dem = ens.dem();
  std::fputs(
      "index,seed,shape,release_x,release_y,release_z,stop_x,stop_y,stop_z,stop_time,runout_m,"
      "reach_angle_deg,max_speed_ms,max_energy_kJ,max_jump_height_m,volume_m3,mass_kg,tree_hits,"
      "tree_energy_kJ,state,steps,checksum\n",
      f);
  for (const RealisationResult& r : runs) {
    const Vec3 a = worldToDem(dem, r.release), b = worldToDem(dem, r.end);
    std::fprintf(
        f,
        "%lld,%llu,%s,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.6g,%.6g,%d,"
        "%.4f,%s,%lld,%s\n",
        static_cast<long long>(r.index), static_cast<unsigned long long>(r.seed),
        ens.ensemble().shapes[static_cast<std::size_t>(r.shape)].c_str(), a.x(), a.y(), a.z(),
        b.x(), b.y(), b.z(), r.endTime, r.runout, r.reachAngle, r.maxSpeed, r.maxEnergy / 1000.0,
        r.maxJumpHeight, r.volume, r.mass, r.treeHits, r.treeEnergy / 1000.0,
        rockStateName(r.state), static_cast<long long>(r.steps), checksumHex(r.checksum).c_str());
  }
}

// paths.csv: every step's centre of mass, DEM coordinates, numbers that read back bit-exact.
void writePathsCsv(std::FILE* f, const Heightfield& dem,
                   const std::vector<RealisationResult>& runs) {
  std::fputs("index,time,x,y,z\n", f);
  for (const RealisationResult& r : runs)
    for (const PathPoint& p : r.path) {
      const Vec3 x = worldToDem(dem, p.x);
      std::fputs(csvRow(r.index, p.time, x.x(), x.y(), x.z()).c_str(), f);
    }
}

void writeConvergence(std::FILE* out, std::FILE* table, const Heightfield& dem,
                      const std::vector<ConvergenceRow>& rows) {
  std::fputs("runs,cell_i,cell_j,x,y,passages,reach_probability,energy_p95_kJ\n", out);
  std::fputs("convergence at the cells with the most passages over all realisations:\n", table);
  std::fprintf(table, "  %8s  %6s %6s  %9s  %11s  %14s\n", "runs", "i", "j", "passages",
               "reach prob.", "energy p95 kJ");
  for (const ConvergenceRow& c : rows) {
    const int i = c.cell % dem.nx, j = c.cell / dem.nx;
    const Vec3 at = worldToDem(dem, Vec3(dem.x0 + i * dem.cell, dem.y0 + j * dem.cell, 0));
    std::fprintf(out, "%lld,%d,%d,%.4f,%.4f,%lld,%.6f,%s\n", static_cast<long long>(c.runs), i, j,
                 at.x(), at.y(), static_cast<long long>(c.passages), c.reachProbability,
                 fmt("%.4f", c.energyP95).c_str());
    std::fprintf(table, "  %8lld  %6d %6d  %9lld  %11.4f  %14s\n", static_cast<long long>(c.runs),
                 i, j, static_cast<long long>(c.passages), c.reachProbability,
                 fmt("%.3f", c.energyP95).c_str());
  }
}

namespace {

// Per statistic: its name, title, units, largest value and files.
nlohmann::ordered_json statisticsJson(const std::vector<StatLayer>& layers) {
  nlohmann::ordered_json stats = nlohmann::ordered_json::array();
  for (const StatLayer& l : layers) {
    double most = NAN;
    for (double v : l.values)
      if (!std::isnan(v) && !(most >= v)) most = v;
    stats.push_back({{"name", l.name},
                     {"title", l.title},
                     {"units", l.units},
                     {"max", number(most)},
                     {"files", {l.name + ".tif", l.name + ".asc"}}});
  }
  return stats;
}

}  // namespace

void writeEnsembleSummary(std::FILE* out, const SceneSpec& spec, const Heightfield& dem,
                          const EnsembleRunInfo& info, const std::vector<RealisationResult>& runs,
                          const std::vector<StatLayer>& layers,
                          const std::vector<ConvergenceRow>& convergence) {
  nlohmann::ordered_json s;
  s["scene"] = spec.name;
  s["seed"] = info.seed;
  s["runs_requested"] = info.runsRequested;
  s["runs"] = runs.size();
  if (info.only) s["only"] = *info.only;
  // An interrupted run's files hold its complete realisations, whichever they are.
  s["interrupted"] = nullptr;
  if (info.stopSignal)
    s["interrupted"] = {{"signal", signalName(info.stopSignal)},
                        {"runs", runs.size()},
                        {"realisations", indexRanges(runs)}};
  int states[4] = {0, 0, 0, 0};
  std::vector<double> runouts, angles;
  for (const RealisationResult& r : runs) {
    ++states[static_cast<int>(r.state)];
    runouts.push_back(r.runout);
    angles.push_back(r.reachAngle);
  }
  s["states"] = {{"stopped", states[1]},
                 {"left", states[2]},
                 {"buried", states[3]},
                 {"moving_at_end", states[0]}};
  s["runout_m"] = distribution(runouts);
  s["reach_angle_deg"] = distribution(angles);
  s["dem"] = {{"path", spec.terrainPath},
              {"nx", dem.nx},
              {"ny", dem.ny},
              {"cell", dem.cell},
              {"crs", dem.crsName}};
  s["statistics"] = statisticsJson(layers);
  s["passage"] =
      "a realisation passes a cell (the DEM pixel) when its centre of mass's straight path over "
      "some step meets the cell; counted once per realisation and cell";
  s["percentile"] = "nearest rank over the realisations that passed the cell";
  if (!convergence.empty()) {
    nlohmann::ordered_json rows = nlohmann::ordered_json::array();
    for (const ConvergenceRow& c : convergence)
      rows.push_back({{"runs", c.runs},
                      {"cell_i", c.cell % dem.nx},
                      {"cell_j", c.cell / dem.nx},
                      {"reach_probability", c.reachProbability},
                      {"energy_p95_kJ", number(c.energyP95)}});
    s["convergence"] = rows;
  }
  const std::string text = s.dump(2) + "\n";
  std::fputs(text.c_str(), out);
}

}  // namespace vf

// Per-cell statistics of an ensemble (see ensemble_stats.h). The reduction reads the
// realisations in index order and nothing else, so the numbers, and the files made from them,
// are the same bytes whatever threads or processes ran the realisations.
#include "sim/ensemble/ensemble_stats.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "sim/core/error.h"

namespace vf {
namespace {

constexpr double kJoulesPerKilojoule = 1000.0;

// Per cell, the values of every passage, realisations in index order (compressed rows).
struct PassageTable {
  std::vector<std::size_t> start;  // nx * ny + 1 offsets
  std::vector<double> energy, height, speed;
};

PassageTable tabulate(std::size_t cells, const std::vector<RealisationResult>& runs,
                      std::size_t firstRuns) {
  PassageTable t;
  t.start.assign(cells + 1, 0);
  for (std::size_t r = 0; r < firstRuns; ++r)
    for (const CellPassage& p : runs[r].cells) ++t.start[static_cast<std::size_t>(p.cell) + 1];
  std::partial_sum(t.start.begin(), t.start.end(), t.start.begin());
  t.energy.resize(t.start.back());
  t.height.resize(t.start.back());
  t.speed.resize(t.start.back());
  std::vector<std::size_t> fill(t.start.begin(), t.start.end() - 1);
  for (std::size_t r = 0; r < firstRuns; ++r)
    for (const CellPassage& p : runs[r].cells) {
      const std::size_t k = fill[static_cast<std::size_t>(p.cell)]++;
      t.energy[k] = p.energy / kJoulesPerKilojoule;
      t.height[k] = p.height;
      t.speed[k] = p.speed;
    }
  return t;
}

}  // namespace

std::vector<StatLayer> cellStatistics(const Heightfield& dem,
                                      const std::vector<RealisationResult>& runs) {
  const std::size_t cells = static_cast<std::size_t>(dem.nx) * static_cast<std::size_t>(dem.ny);
  PassageTable t = tabulate(cells, runs, runs.size());
  const double n = static_cast<double>(runs.size());
  auto layer = [&](const char* name, const char* title, const char* units, double empty) {
    return StatLayer{name, title, units, std::vector<double>(cells, empty)};
  };
  std::vector<StatLayer> out;
  out.push_back(layer("passages", "Passages (realisations through the cell)", "count", 0));
  out.push_back(layer("reach_probability", "Reach probability", "fraction", 0));
  out.push_back(layer("energy_mean", "Kinetic energy, mean", "kJ", NAN));
  out.push_back(layer("energy_p50", "Kinetic energy, median", "kJ", NAN));
  out.push_back(layer("energy_p95", "Kinetic energy, 95th percentile", "kJ", NAN));
  out.push_back(layer("energy_max", "Kinetic energy, maximum", "kJ", NAN));
  out.push_back(layer("height_p95", "Passing height above ground, 95th percentile", "m", NAN));
  out.push_back(layer("speed_p95", "Speed, 95th percentile", "m/s", NAN));
  out.push_back(layer("deposited", "Deposited rocks (stopped in the cell)", "count", 0));
  for (std::size_t c = 0; c < cells; ++c) {
    const std::size_t a = t.start[c], b = t.start[c + 1], m = b - a;
    if (m == 0) continue;
    out[0].values[c] = static_cast<double>(m);
    out[1].values[c] = static_cast<double>(m) / n;
    double sum = 0;  // in realisation order, before sorting
    for (std::size_t k = a; k < b; ++k) sum += t.energy[k];
    out[2].values[c] = sum / static_cast<double>(m);
    std::sort(t.energy.begin() + a, t.energy.begin() + b);
    std::sort(t.height.begin() + a, t.height.begin() + b);
    std::sort(t.speed.begin() + a, t.speed.begin() + b);
    out[3].values[c] = nearestRankPercentile(t.energy.data() + a, m, 50);
    out[4].values[c] = nearestRankPercentile(t.energy.data() + a, m, 95);
    out[5].values[c] = t.energy[b - 1];
    out[6].values[c] = nearestRankPercentile(t.height.data() + a, m, 95);
    out[7].values[c] = nearestRankPercentile(t.speed.data() + a, m, 95);
  }
  std::vector<std::int32_t> at;
  for (const RealisationResult& r : runs) {
    if (r.state != RockState::kStopped) continue;
    at.clear();
    cellsOnSegment(dem, r.end, r.end, at);
    if (!at.empty()) out[8].values[static_cast<std::size_t>(at.front())] += 1;
  }
  return out;
}

std::vector<ConvergenceRow> convergence(const Heightfield& dem,
                                        const std::vector<RealisationResult>& runs, int cellCount) {
  const std::size_t cells = static_cast<std::size_t>(dem.nx) * static_cast<std::size_t>(dem.ny);
  std::vector<ConvergenceRow> rows;
  if (runs.empty()) return rows;
  std::vector<std::int64_t> count(cells, 0);
  for (const RealisationResult& r : runs)
    for (const CellPassage& p : r.cells) ++count[static_cast<std::size_t>(p.cell)];
  std::vector<std::int32_t> order(cells);
  std::iota(order.begin(), order.end(), 0);
  const std::size_t k = std::min<std::size_t>(static_cast<std::size_t>(cellCount), cells);
  std::partial_sort(
      order.begin(), order.begin() + static_cast<std::ptrdiff_t>(k), order.end(),
      [&](std::int32_t a, std::int32_t b) {
        return count[static_cast<std::size_t>(a)] != count[static_cast<std::size_t>(b)]
                   ? count[static_cast<std::size_t>(a)] > count[static_cast<std::size_t>(b)]
                   : a < b;
      });
  const std::size_t total = runs.size();
  std::vector<std::size_t> sizes;
  for (std::size_t div : {8, 4, 2, 1})
    if (total / div >= 1 && (sizes.empty() || sizes.back() != total / div))
      sizes.push_back(total / div);
  for (std::size_t n : sizes) {
    PassageTable t = tabulate(cells, runs, n);
    for (std::size_t q = 0; q < k; ++q) {
      const std::size_t c = static_cast<std::size_t>(order[q]);
      const std::size_t a = t.start[c], b = t.start[c + 1];
      ConvergenceRow row;
      row.runs = static_cast<std::int64_t>(n);
      row.cell = order[q];
      row.passages = static_cast<std::int64_t>(b - a);
      row.reachProbability = static_cast<double>(b - a) / static_cast<double>(n);
      row.energyP95 = NAN;
      if (b > a) {
        std::sort(t.energy.begin() + a, t.energy.begin() + b);
        row.energyP95 = nearestRankPercentile(t.energy.data() + a, b - a, 95);
      }
      rows.push_back(row);
    }
  }
  return rows;
}

}  // namespace vf

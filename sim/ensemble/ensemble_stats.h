// Per-cell statistics of an ensemble on the DEM's grid (README, "Ensembles and hazard maps").
// Every statistic is a vector of dem.nx * dem.ny values in Heightfield::z's layout (sample
// (i, j) at j * nx + i, j from the south), NaN where it has no value, with a name (file
// stem), a title and units: what a hazard map layer needs.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "sim/core/percentile.h"
#include "sim/ensemble/ensemble.h"
#include "sim/shape/heightfield.h"

namespace vf {

struct StatLayer {
  std::string name;            // file stem, e.g. "energy_p95"
  std::string title;           // e.g. "Kinetic energy, 95th percentile"
  std::string units;           // e.g. "kJ"
  std::vector<double> values;  // dem.nx * dem.ny; NaN = no value
};

// The statistics of `runs` (complete realisations, in index order) in this fixed order:
// passages, reach_probability, energy_mean, energy_p50, energy_p95, energy_max, height_p95,
// speed_p95, deposited. Passage values are those of ensemble.h (CellPassage); energies in kJ.
// Cells no realisation passed have 0 passages, reach probability 0, 0 deposited and NaN for
// the others. Memory: one value per passage and statistic, kept until the percentiles are
// taken (about 24 bytes per cell a realisation passes: fine for thousands of realisations).
std::vector<StatLayer> cellStatistics(const Heightfield& dem,
                                      const std::vector<RealisationResult>& runs);

// Convergence (--converge): at the `cellCount` cells with the most passages over all `runs`
// (ties: the lower cell index), the reach probability and 95th-percentile energy over the
// first N/8, N/4, N/2 and N realisations.
struct ConvergenceRow {
  std::int64_t runs = 0;
  std::int32_t cell = 0;  // j * nx + i
  std::int64_t passages = 0;
  double reachProbability = 0;
  double energyP95 = 0;  // kJ; NaN without passages
};
std::vector<ConvergenceRow> convergence(const Heightfield& dem,
                                        const std::vector<RealisationResult>& runs,
                                        int cellCount = 3);

}  // namespace vf

// A scene's [forest] -> the stand on the DEM's grid (sim/ground/forest.h): rasters resampled by
// GDAL (sim/shape/dem_grid_raster.h), tree points counted per cell (sim/shape/tree_points.h),
// numbers spread over every sample, and every value checked
// before a step is taken, so bad input stops the run before anything is written.
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "sim/core/error.h"
#include "sim/ground/forest.h"
#include "sim/scene/scene.h"
#include "sim/shape/dem_grid_raster.h"
#include "sim/shape/tree_points.h"

namespace vf {
namespace {

// Where sample k lies, for messages: its grid indices and world coordinates.
std::string samplePlace(const Heightfield& dem, std::size_t k) {
  const int i = static_cast<int>(k % dem.nx), j = static_cast<int>(k / dem.nx);
  char buf[120];
  std::snprintf(buf, sizeof buf, "DEM sample (%d, %d) at x %.2f, y %.2f", i, j,
                dem.x0 + i * dem.cell, dem.y0 + j * dem.cell);
  return buf;
}

// One quantity on every sample: its raster resampled, or the number everywhere. A raster's
// no-data samples stay NaN; a negative value is an error naming the file and the place.
std::vector<double> quantity(const std::string& path, double value, const Heightfield& dem,
                             const std::string& what, const std::string& unit) {
  if (path.empty()) return std::vector<double>(dem.z.size(), value);
  std::vector<double> v = loadOnDemGrid(path, dem, GridResampling::kBilinear, what);
  for (std::size_t k = 0; k < v.size(); ++k)
    if (v[k] < 0)
      throw InputError(path, what + " " + std::to_string(v[k]) + " " + unit + " at " +
                                 samplePlace(dem, k) + ": it cannot be negative");
  return v;
}

// Species classes on every sample (0 where the raster has no data), each an integer with a
// factor in `factors`.
std::vector<int> speciesClasses(const ForestSpec& f, const Heightfield& dem, std::size_t classes) {
  const std::vector<double> v =
      loadOnDemGrid(f.speciesPath, dem, GridResampling::kNearest, "species class");
  std::vector<int> out(v.size(), 0);
  for (std::size_t k = 0; k < v.size(); ++k) {
    if (std::isnan(v[k])) continue;
    if (v[k] < 0 || v[k] != std::floor(v[k]) || v[k] >= static_cast<double>(classes))
      throw InputError(f.speciesPath, "species class " + std::to_string(v[k]) + " at " +
                                          samplePlace(dem, k) +
                                          " has no factor: 'species_factors' gives classes 0 .. " +
                                          std::to_string(classes - 1));
    out[k] = static_cast<int>(v[k]);
  }
  return out;
}

}  // namespace

std::shared_ptr<const Forest> buildSceneForest(const SceneSpec& spec,
                                               std::shared_ptr<const Heightfield> terrain) {
  if (!spec.forest) return nullptr;
  const ForestSpec& f = *spec.forest;
  if (!terrain)
    throw InputError(f.where, "[forest] lies on the DEM's grid: give [ground] heightfield");
  const Heightfield& dem = *terrain;
  auto forest = std::make_shared<Forest>();
  forest->grid = terrain;
  if (!f.treesPath.empty()) {
    TreeStand trees = loadTreePoints(f.treesPath, f.treesDbhField, dem);
    forest->density = std::move(trees.density);
    forest->dbh = std::move(trees.dbh);
  } else {
    forest->density = quantity(f.densityPath, f.densityValue, dem, "stem density", "stems/ha");
    forest->dbh = quantity(f.dbhPath, f.dbhValue, dem, "mean DBH", "cm");
  }
  forest->speciesFactor = f.speciesFactors.empty() ? std::vector<double>{1.0} : f.speciesFactors;
  if (!f.speciesPath.empty())
    forest->species = speciesClasses(f, dem, forest->speciesFactor.size());
  for (std::size_t k = 0; k < forest->density.size(); ++k)
    if (forest->density[k] > 0 && std::isnan(forest->dbh[k]))
      throw InputError(f.dbhPath, "mean DBH has no data at " + samplePlace(dem, k) +
                                      ", where the "
                                      "stem density is " +
                                      std::to_string(forest->density[k]) + " stems/ha");
  forest->stemHeight = f.stemHeight;
  return forest;
}

}  // namespace vf

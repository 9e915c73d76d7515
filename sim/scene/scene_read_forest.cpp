// [forest]: a stand on the DEM's grid (sim/ground/forest.h): stem density and mean DBH, each a
// raster or one number, or a point file of trees; optionally a species class raster with a
// factor per class.
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "sim/scene/scene_keys.h"
#include "sim/scene/scene_reader.h"

namespace vf::scene_reading {

namespace {

// `key` as a raster path (resolved, must exist) or as one number >= 0 in `unit`.
void rasterOrNumber(const Reader& r, const toml::node& n, const std::string& key,
                    const fs::path& sceneFolder, const std::string& what, const std::string& unit,
                    std::string& path, double& value) {
  if (n.is_string())
    path = existingFile(r, n, key, sceneFolder, what + " raster");
  else if (n.is_number())
    value = r.nonNegative(n, key, " " + unit);
  else
    r.fail(n, "'" + key + "' must be a raster file (a string) or a number in " + unit + ", got " +
                  typeName(n));
}

}  // namespace

void readForest(const Reader& r, const toml::table& t, const fs::path& sceneFolder,
                SceneSpec& spec) {
  r.checkKeys(t, sceneKeysOf("forest"), "[forest]");
  if (spec.terrainPath.empty())
    r.fail(t, "[forest] lies on the DEM's grid; give [ground] heightfield");
  ForestSpec f;
  f.where = r.where(t);
  if (const auto* n = t.get("trees")) {
    for (const char* key : {"density", "dbh"})
      if (const auto* other = t.get(key))
        r.fail(*other, "'" + std::string(key) +
                           "' and 'trees' both describe the stand; give the rasters or the points");
    f.treesPath = existingFile(r, *n, "trees", sceneFolder, "tree point file");
  } else {
    rasterOrNumber(r, r.require(t, "density", "[forest] (or give 'trees')"), "density", sceneFolder,
                   "stem density", "stems/ha", f.densityPath, f.densityValue);
    rasterOrNumber(r, r.require(t, "dbh", "[forest]"), "dbh", sceneFolder, "mean DBH", "cm",
                   f.dbhPath, f.dbhValue);
  }
  if (const auto* n = t.get("trees_dbh_field")) {
    if (!t.get("trees")) r.fail(*n, "'trees_dbh_field' names a field of 'trees'; give 'trees' too");
    f.treesDbhField = r.string(*n, "trees_dbh_field");
  }
  if (const auto* n = t.get("species"))
    f.speciesPath = existingFile(r, *n, "species", sceneFolder, "species class raster");
  if (const auto* n = t.get("species_factors")) {
    const toml::array* a = n->as_array();
    if (a == nullptr || a->empty())
      r.fail(*n,
             "'species_factors' must be an array of numbers >= 0, one per species class from "
             "0, got " +
                 typeName(*n));
    for (std::size_t i = 0; i < a->size(); ++i)
      f.speciesFactors.push_back(
          r.nonNegative(*a->get(i), "species_factors[" + std::to_string(i) + "]", ""));
  }
  if (const auto* n = t.get("stem_height")) f.stemHeight = r.positive(*n, "stem_height", " m");
  if (const auto* n = t.get("seed"))
    f.seed = static_cast<std::uint64_t>(
        r.integerInRange(*n, "seed", 0, std::numeric_limits<std::int64_t>::max()));
  spec.forest = f;
}

}  // namespace vf::scene_reading

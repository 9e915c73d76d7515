// A scene's [forest] rasters onto the DEM's grid (sim/shape/dem_grid_raster.cpp,
// sim/scene/scene_forest.cpp): GDAL's resampling against values known in closed form, and every
// bad form of the input refused with one message naming the file and what is wrong.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <functional>
#include <sstream>
#include <string>
#include <vector>

#include "sim/core/error.h"
#include "sim/ground/forest.h"
#include "sim/ground/rock_fall.h"
#include "sim/scene/scene.h"
#include "tests/support/chute_dem.h"

namespace vf {
namespace {

// A raster in the chute DEM's (EPSG:31287) or another CRS, any cell size and corner; value(x, y)
// at each cell's centre (file coordinates). epsg 0: no CRS; georeferenced false: no geotransform.
struct Raster {
  int nx = 60, ny = 12;
  double cell = 2.0, west = 1000.0, north = 5024.0;  // the chute DEM's grid by default
  int epsg = 31287;
  bool georeferenced = true;
  std::function<double(double, double)> value = [](double, double) { return 400.0; };
};

void writeRaster(const std::filesystem::path& path, const Raster& r) {
  GDALAllRegister();
  GDALDatasetH ds =
      GDALCreate(GDALGetDriverByName("GTiff"), path.c_str(), r.nx, r.ny, 1, GDT_Float64, nullptr);
  ASSERT_NE(ds, nullptr);
  double gt[6] = {r.west, r.cell, 0, r.north, 0, -r.cell};
  if (r.georeferenced) GDALSetGeoTransform(ds, gt);
  if (r.epsg != 0) test::setEpsg(ds, r.epsg);
  std::vector<double> v(static_cast<std::size_t>(r.nx) * r.ny);
  for (int row = 0; row < r.ny; ++row)
    for (int i = 0; i < r.nx; ++i)
      v[static_cast<std::size_t>(row) * r.nx + i] =
          r.value(r.west + (i + 0.5) * r.cell, r.north - (row + 0.5) * r.cell);
  ASSERT_EQ(GDALRasterIO(GDALGetRasterBand(ds, 1), GF_Write, 0, 0, r.nx, r.ny, v.data(), r.nx, r.ny,
                         GDT_Float64, 0, 0),
            CE_None);
  GDALClose(ds);
}

class ForestInput : public test::ChuteFolderTest {
 protected:
  // The stand of a spec whose density raster is `density` (written here) and DBH 30 cm.
  std::shared_ptr<const Forest> standOf(const Raster& density, const std::string& name = "d.tif") {
    writeRaster(dir_ / name, density);
    return build((dir_ / name).string());
  }
  std::shared_ptr<const Forest> build(const std::string& densityPath) {
    SceneSpec spec;
    spec.terrainPath = (dir_ / "chute.tif").string();
    spec.forest.emplace();
    spec.forest->densityPath = densityPath;
    spec.forest->dbhValue = 30;
    spec.forest->speciesPath = speciesPath_;
    spec.forest->speciesFactors = factors_;
    return buildSceneForest(spec, loadSceneTerrain(spec));
  }
  // The message of the InputError building the stand throws.
  std::string errorOf(const Raster& density, const std::string& name = "d.tif") {
    try {
      standOf(density, name);
    } catch (const InputError& e) {
      return e.what();
    }
    return "no error";
  }
  std::string speciesPath_;
  std::vector<double> factors_;
};

}  // namespace

// On the DEM's own grid the values come back sample for sample (north row of the file = the
// last row of ours).
TEST_F(ForestInput, ARasterOnTheDemsGridIsReadSampleForSample) {
  Raster r;
  r.value = [](double x, double y) { return (x - 1000) + 1000 * (y - 5000); };
  const auto f = standOf(r);
  const Heightfield& dem = *f->grid;
  for (int j = 0; j < dem.ny; ++j)
    for (int i = 0; i < dem.nx; ++i)
      ASSERT_EQ(f->density[static_cast<std::size_t>(j) * dem.nx + i],
                (1 + 2 * i) + 1000.0 * (1 + 2 * j))
          << i << ", " << j;
}

// A coarser raster (5 m cells) over a larger extent is resampled by GDAL's bilinear warp, which
// reproduces a linear field exactly between cell centres: density = 100 + 2 (x - 990) + (y -
// 4990) at each DEM sample's (file) coordinates, to rounding.
TEST_F(ForestInput, ACoarserRasterIsResampledBilinearlyOntoTheDem) {
  Raster r;
  r.cell = 5, r.west = 990, r.north = 5035, r.nx = 30, r.ny = 10;
  const auto field = [](double x, double y) { return 100 + 2 * (x - 990) + (y - 4990); };
  r.value = field;
  const auto f = standOf(r);
  const Heightfield& dem = *f->grid;
  for (int j = 0; j < dem.ny; ++j)
    for (int i = 0; i < dem.nx; ++i)
      ASSERT_NEAR(f->density[static_cast<std::size_t>(j) * dem.nx + i],
                  field(1001 + 2 * i, 5001 + 2 * j), 1e-6)
          << i << ", " << j;
}

TEST_F(ForestInput, AMissingRasterIsNamed) {
  const std::string path = (dir_ / "nowhere.tif").string();
  try {
    build(path);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("cannot read the stem density raster"), std::string::npos)
        << e.what();
  }
}

TEST_F(ForestInput, ARasterInAnotherCrsIsRefusedNamingBoth) {
  Raster r;
  r.epsg = 32632;  // UTM 32N, metres too: same numbers, another place on the Earth
  const std::string m = errorOf(r);
  EXPECT_NE(m.find((dir_ / "d.tif").string()), std::string::npos) << m;
  EXPECT_NE(m.find("EPSG:32632"), std::string::npos) << m;
  EXPECT_NE(m.find("EPSG:31287"), std::string::npos) << m;
  // The same raster with no CRS is taken to be in the DEM's.
  r.epsg = 0;
  EXPECT_EQ(errorOf(r, "nocrs.tif"), "no error");
}

TEST_F(ForestInput, ARasterThatDoesNotCoverTheDemIsRefused) {
  Raster r;
  r.nx = 59;  // the eastern column of cells is missing
  const std::string m = errorOf(r);
  EXPECT_NE(m.find((dir_ / "d.tif").string()), std::string::npos) << m;
  EXPECT_NE(m.find("does not cover the DEM"), std::string::npos) << m;
}

TEST_F(ForestInput, ARasterWithoutGeoreferenceIsRefused) {
  Raster r;
  r.georeferenced = false;
  r.epsg = 0;
  const std::string m = errorOf(r);
  EXPECT_NE(m.find("no georeference"), std::string::npos) << m;
}

TEST_F(ForestInput, ANegativeDensityIsRefusedWithItsPlace) {
  Raster r;
  r.value = [](double x, double y) { return x > 1050 && y > 5010 ? -5.0 : 400.0; };
  const std::string m = errorOf(r);
  EXPECT_NE(m.find((dir_ / "d.tif").string()), std::string::npos) << m;
  EXPECT_NE(m.find("stem density -5"), std::string::npos) << m;
  EXPECT_NE(m.find("cannot be negative"), std::string::npos) << m;
}

TEST_F(ForestInput, ASpeciesClassWithoutAFactorIsRefused) {
  Raster classes;
  classes.value = [](double x, double) { return x > 1100 ? 2.0 : 1.0; };
  writeRaster(dir_ / "species.tif", classes);
  speciesPath_ = (dir_ / "species.tif").string();
  factors_ = {1.0, 0.8};  // classes 0 and 1
  Raster density;
  const std::string m = errorOf(density);
  EXPECT_NE(m.find(speciesPath_), std::string::npos) << m;
  EXPECT_NE(m.find("species class 2"), std::string::npos) << m;
  factors_ = {1.0, 0.8, 1.3};
  const auto f = standOf(density);
  EXPECT_EQ(f->species.front(), 1);  // x = 1001: class 1
  EXPECT_EQ(f->species[59], 2);      // x = 1119: class 2
  Forest::Stand s;
  ASSERT_TRUE(f->standAt(1119, 5001, s));
  EXPECT_EQ(s.speciesFactor, 1.3);
}

// The scene file's [forest]: a missing raster is named where the scene names it; a negative
// number is refused at its key; a raster's value problems come when the world is built, before
// any step.
TEST_F(ForestInput, TheSceneTableNamesAMissingFileAndRefusesANegativeNumber) {
  const auto errorOfScene = [&](const std::string& forest) {
    test::writeChuteScene(dir_, test::kChuteEnsemble, 3.0);
    std::ofstream(dir_ / "scene.toml", std::ios::app) << "[forest]\n" << forest;
    try {
      const SceneSpec spec = loadScene((dir_ / "scene.toml").string());
      sceneRockFallDef(spec, sceneWorldDef(spec).terrain);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  std::string m = errorOfScene("density = \"trees.tif\"\ndbh = 30\n");
  EXPECT_NE(m.find("stem density raster not found"), std::string::npos) << m;
  EXPECT_NE(m.find((dir_ / "trees.tif").string()), std::string::npos) << m;
  m = errorOfScene("density = -3\ndbh = 30\n");
  EXPECT_NE(m.find("'density' must be >= 0 stems/ha"), std::string::npos) << m;
  m = errorOfScene("density = 400\n");
  EXPECT_NE(m.find("missing required key 'dbh'"), std::string::npos) << m;
  Raster negative;
  negative.value = [](double, double) { return -1.0; };
  writeRaster(dir_ / "trees.tif", negative);
  m = errorOfScene("density = \"trees.tif\"\ndbh = 30\n");
  EXPECT_NE(m.find((dir_ / "trees.tif").string() + ": stem density -1"), std::string::npos) << m;
  EXPECT_EQ(errorOfScene("density = 400\ndbh = 30\nseed = 7\n"), "no error");
}

// A GeoJSON point file of trees in EPSG:`epsg` (0: no "crs" member, so WGS 84), each "x y dbh"
// (file coordinates, cm); a dbh of "null" leaves the field empty.
std::string treeFile(const std::filesystem::path& path, int epsg,
                     const std::vector<std::string>& trees) {
  std::ofstream f(path);
  f << "{\"type\": \"FeatureCollection\",";
  if (epsg != 0)
    f << "\"crs\": {\"type\": \"name\", \"properties\": {\"name\": \"urn:ogc:def:crs:EPSG::" << epsg
      << "\"}},";
  f << "\"features\": [";
  for (std::size_t k = 0; k < trees.size(); ++k) {
    std::istringstream in(trees[k]);
    std::string x, y, dbh;
    in >> x >> y >> dbh;
    f << (k ? "," : "") << "{\"type\": \"Feature\", \"properties\": {\"dbh\": " << dbh
      << "}, \"geometry\": {\"type\": \"Point\", \"coordinates\": [" << x << ", " << y << "]}}";
  }
  f << "]}";
  return path.string();
}

// Trees count in the cell of their nearest DEM sample: two in the 4 m^2 cell of sample (3, 4)
// (file x 1007, y 5009) make 2 / 0.0004 ha = 5000 stems/ha of mean DBH (20 + 30) / 2 = 25 cm; a
// tree beyond the grid is left out; every other cell has none.
TEST_F(ForestInput, TreePointsBecomeADensityAndAMeanDbhPerCell) {
  SceneSpec spec;
  spec.terrainPath = (dir_ / "chute.tif").string();
  spec.forest.emplace();
  spec.forest->treesPath = treeFile(dir_ / "trees.geojson", 31287,
                                    {"1007.2 5009.3 20", "1006.4 5008.8 30", "900 5000 50"});
  const auto f = buildSceneForest(spec, loadSceneTerrain(spec));
  const std::size_t k = 4 * 60 + 3;
  EXPECT_DOUBLE_EQ(f->density[k], 5000.0);
  EXPECT_DOUBLE_EQ(f->dbh[k], 25.0);
  double total = 0;
  for (double d : f->density) total += d;
  EXPECT_DOUBLE_EQ(total, 5000.0);
}

TEST_F(ForestInput, BadTreePointFilesAreRefusedNamingTheFileAndTheFeature) {
  const auto errorOfTrees = [&](const std::string& path, const std::string& field = "dbh") {
    SceneSpec spec;
    spec.terrainPath = (dir_ / "chute.tif").string();
    spec.forest.emplace();
    spec.forest->treesPath = path;
    spec.forest->treesDbhField = field;
    try {
      buildSceneForest(spec, loadSceneTerrain(spec));
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  const std::string ok = treeFile(dir_ / "ok.geojson", 31287, {"1007 5009 20"});
  EXPECT_EQ(errorOfTrees(ok), "no error");
  // Points in another CRS are transformed into the DEM's (the shared vector reader): the same
  // numbers in UTM 32N lie hundreds of kilometres away, off the grid.
  std::string m = errorOfTrees(treeFile(dir_ / "utm.geojson", 32632, {"1007 5009 20"}));
  EXPECT_NE(
      m.find((dir_ / "utm.geojson").string() + ": no tree of the point file stands on the DEM"),
      std::string::npos)
      << m;
  m = errorOfTrees(treeFile(dir_ / "neg.geojson", 31287, {"1007 5009 20", "1009 5009 -4"}));
  EXPECT_NE(m.find("feature 1 has DBH -4"), std::string::npos) << m;
  m = errorOfTrees(treeFile(dir_ / "null.geojson", 31287, {"1007 5009 null"}));
  EXPECT_NE(m.find("feature 0 has no DBH"), std::string::npos) << m;
  m = errorOfTrees(ok, "diameter");
  EXPECT_NE(m.find("no numeric field 'diameter'"), std::string::npos) << m;
  m = errorOfTrees((dir_ / "none.geojson").string());
  EXPECT_NE(m.find((dir_ / "none.geojson").string() + ": vector file not found"), std::string::npos)
      << m;
}

}  // namespace vf

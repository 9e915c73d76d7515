// voxfall ensemble's outputs in place on the Earth, on the synthetic chute
// (tests/support/chute_dem.h): the rasters carry the DEM's georeference and CRS, or the CRS the
// scene gives a DEM without one; they are NODATA exactly where the DEM is; a CRS that conflicts
// or that GDAL does not know is one error; --extent chooses the maps' window.
#include <gdal.h>
#include <gtest/gtest.h>
#include <ogr_srs_api.h>

#include <filesystem>
#include <string>
#include <vector>

#include "render/maps/hazard_map.h"
#include "render/output/png_writer.h"
#include "tests/support/chute_dem.h"
#include "tests/support/voxfall_command.h"

namespace {

namespace fs = std::filesystem;
using vf::test::readFile;
using vf::test::runVoxfall;

const std::string kExe = VOXFALL_EXE;

using EnsembleGeorefTest = vf::test::ChuteFolderTest;

TEST_F(EnsembleGeorefTest, RastersCarryTheInputGeoreferenceAndCrs) {
  vf::test::writeChuteScene(dir_, vf::test::kChuteEnsemble);
  const auto r = runVoxfall(kExe, dir_, "ensemble scene.toml --runs 4 -q -o geo");
  ASSERT_EQ(r.code, 0) << r.err;
  GDALAllRegister();
  GDALDatasetH in = GDALOpen((dir_ / "chute.tif").c_str(), GA_ReadOnly);
  ASSERT_NE(in, nullptr);
  double gtIn[6];
  ASSERT_EQ(GDALGetGeoTransform(in, gtIn), CE_None);
  OGRSpatialReferenceH srsIn = OSRNewSpatialReference(GDALGetProjectionRef(in));
  for (const char* name : {"energy_p95.tif", "energy_p95.asc", "reach_probability.tif"}) {
    GDALDatasetH out = GDALOpen((dir_ / "geo" / name).c_str(), GA_ReadOnly);
    ASSERT_NE(out, nullptr) << name;
    EXPECT_EQ(GDALGetRasterXSize(out), GDALGetRasterXSize(in)) << name;
    EXPECT_EQ(GDALGetRasterYSize(out), GDALGetRasterYSize(in)) << name;
    double gt[6];
    ASSERT_EQ(GDALGetGeoTransform(out, gt), CE_None) << name;
    // ESRI ASCII stores corner and cell size as decimal text: equal to the last digit GDAL
    // prints (1e-9 m on kilometre coordinates); GeoTIFF stores the doubles.
    const double tol = std::string(name).ends_with(".asc") ? 1e-9 : 0.0;
    for (int k = 0; k < 6; ++k) EXPECT_NEAR(gt[k], gtIn[k], tol) << name << " gt[" << k << "]";
    OGRSpatialReferenceH srs = OSRNewSpatialReference(GDALGetProjectionRef(out));
    // The ASCII grid's CRS is GDAL's ESRI .prj, which spells datum names the ESRI way: the same
    // CRS by definition (projection, parameters, datum, units), not by name.
    const char* const criterion[] = {"CRITERION=EQUIVALENT", nullptr};
    EXPECT_TRUE(OSRIsSameEx(srs, srsIn, criterion)) << name << ": " << GDALGetProjectionRef(out);
    OSRDestroySpatialReference(srs);
    GDALClose(out);
  }
  OSRDestroySpatialReference(srsIn);
  GDALClose(in);
}

// True if the raster `path` (its .prj for an ASCII grid) is in EPSG:31287.
bool inAustriaLambert(const fs::path& path) {
  GDALAllRegister();
  GDALDatasetH ds = GDALOpen(path.c_str(), GA_ReadOnly);
  if (!ds) return false;
  OGRSpatialReferenceH got = OSRNewSpatialReference(GDALGetProjectionRef(ds));
  OGRSpatialReferenceH want = OSRNewSpatialReference(nullptr);
  OSRImportFromEPSG(want, 31287);
  const char* const criterion[] = {"CRITERION=EQUIVALENT", nullptr};
  const bool same = got && *GDALGetProjectionRef(ds) && OSRIsSameEx(got, want, criterion);
  OSRDestroySpatialReference(got);
  OSRDestroySpatialReference(want);
  GDALClose(ds);
  return same;
}

TEST_F(EnsembleGeorefTest, ASceneGivesItsCrsToADemThatHasNone) {
  vf::test::ChuteDem bare;
  bare.crs = false;
  ASSERT_TRUE(vf::test::writeChuteDem(dir_ / "chute.tif", bare));
  // Without the key the rasters have no CRS (the control: the check below can fail).
  vf::test::writeChuteScene(dir_, vf::test::kChuteEnsemble);
  auto r = runVoxfall(kExe, dir_, "ensemble scene.toml --runs 2 -q -o none");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_FALSE(inAustriaLambert(dir_ / "none" / "energy_p95.tif"));
  EXPECT_FALSE(fs::exists(dir_ / "none" / "energy_p95.prj"));
  vf::test::writeChuteScene(dir_, vf::test::kChuteEnsemble, 3.0, "crs = \"EPSG:31287\"\n");
  r = runVoxfall(kExe, dir_, "ensemble scene.toml --runs 2 -q -o crs");
  ASSERT_EQ(r.code, 0) << r.err;
  for (const char* name : {"energy_p95.tif", "energy_p95.asc", "reach_probability.tif"})
    EXPECT_TRUE(inAustriaLambert(dir_ / "crs" / name)) << name;
  EXPECT_TRUE(fs::exists(dir_ / "crs" / "energy_p95.prj"));
  EXPECT_NE(readFile(dir_ / "crs" / "summary.json").find("EPSG:31287"), std::string::npos);
}

TEST_F(EnsembleGeorefTest, ACrsOtherThanTheDemsOwnIsRefusedAndWritesNothing) {
  vf::test::writeChuteScene(dir_, vf::test::kChuteEnsemble, 3.0, "crs = \"EPSG:4326\"\n");
  const auto r = runVoxfall(kExe, dir_, "ensemble scene.toml --runs 2 -q -o out");
  EXPECT_NE(r.code, 0);
  EXPECT_NE(r.err.find("chute.tif"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("EPSG:31287"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("EPSG:4326"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir_ / "out" / "runs.csv"));
  // The DEM's own CRS, given again, is accepted.
  vf::test::writeChuteScene(dir_, vf::test::kChuteEnsemble, 3.0, "crs = \"EPSG:31287\"\n");
  EXPECT_EQ(runVoxfall(kExe, dir_, "ensemble scene.toml --runs 2 -q -o same").code, 0);
}

TEST_F(EnsembleGeorefTest, ACrsGdalDoesNotKnowIsOneErrorAtItsLine) {
  for (const char* bad : {"EPSG:0", "LOCAL_CS[\\\"site\\\"]"}) {
    vf::test::writeChuteScene(dir_, vf::test::kChuteEnsemble, 3.0,
                              std::string("crs = \"") + bad + "\"\n");
    const auto r = runVoxfall(kExe, dir_, "ensemble scene.toml --runs 2 -q -o out");
    EXPECT_EQ(r.code, 1) << bad;
    EXPECT_NE(r.err.find("scene.toml:9"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("crs"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(dir_ / "out"));
  }
}

// Band 1 of a raster, rows from the north, and its NODATA value.
std::vector<double> readBand(const fs::path& path, double& noData) {
  GDALAllRegister();
  GDALDatasetH ds = GDALOpen(path.c_str(), GA_ReadOnly);
  if (!ds) return {};
  const int nx = GDALGetRasterXSize(ds), ny = GDALGetRasterYSize(ds);
  std::vector<double> v(static_cast<std::size_t>(nx) * ny);
  GDALRasterBandH band = GDALGetRasterBand(ds, 1);
  int has = 0;
  noData = GDALGetRasterNoDataValue(band, &has);
  if (!has ||
      GDALRasterIO(band, GF_Read, 0, 0, nx, ny, v.data(), nx, ny, GDT_Float64, 0, 0) != CE_None)
    v.clear();
  GDALClose(ds);
  return v;
}

TEST_F(EnsembleGeorefTest, EveryRasterIsNodataExactlyWhereTheDemIs) {
  vf::test::ChuteDem holed;
  holed.noDataCorner = 3;
  ASSERT_TRUE(vf::test::writeChuteDem(dir_ / "chute.tif", holed));
  vf::test::writeChuteScene(dir_, vf::test::kChuteEnsemble);
  const auto r = runVoxfall(kExe, dir_, "ensemble scene.toml --runs 4 -q -o holed");
  ASSERT_EQ(r.code, 0) << r.err;
  double demNoData = 0;
  const std::vector<double> dem = readBand(dir_ / "chute.tif", demNoData);
  ASSERT_EQ(dem.size(), static_cast<std::size_t>(holed.nx * holed.ny));
  for (const char* name : {"passages.tif", "reach_probability.asc", "deposited.tif"}) {
    double noData = 0;
    const std::vector<double> v = readBand(dir_ / "holed" / name, noData);
    ASSERT_EQ(v.size(), dem.size()) << name;
    int holes = 0, zeros = 0;
    for (std::size_t c = 0; c < v.size(); ++c) {
      const bool demHole = dem[c] == demNoData;
      EXPECT_EQ(v[c] == noData, demHole) << name << " sample " << c;
      holes += demHole;
      zeros += !demHole && v[c] == 0;
    }
    EXPECT_EQ(holes, 9) << name;
    EXPECT_GT(zeros, 0) << name;  // cells with data that no rock reached still hold 0
  }
}

TEST_F(EnsembleGeorefTest, ExtentChoosesTheMapsWindowAndABadOneWritesNothing) {
  vf::test::writeChuteScene(dir_, vf::test::kChuteEnsemble);
  // File coordinates: samples at x = 1001 + 2 i, y = 5001 + 2 j; this box holds i 5..24, j 1..9.
  auto r = runVoxfall(kExe, dir_,
                      "ensemble scene.toml --runs 4 --maps --extent 1010,5002,1050,5020 -q -o ext");
  ASSERT_EQ(r.code, 0) << r.err;
  vf::Heightfield dem = vf::loadDem((dir_ / "chute.tif").string());
  vf::shiftHeightfield(dem, vf::Vec3(-1000, -5000, 0));
  const vf::MapWindow w = vf::extentWindow(dem, 1010, 5002, 1050, 5020);
  EXPECT_EQ(w.i0, 5);
  EXPECT_EQ(w.ni, 20);
  EXPECT_EQ(w.j0, 1);
  EXPECT_EQ(w.nj, 9);
  const vf::MapFrame f = vf::hazardMapFrame(dem, w);
  for (const char* name : {"reach_probability.png", "intensity.png"}) {
    const vf::Image map = vf::readPng((dir_ / "ext" / name).string());
    EXPECT_EQ(map.width, f.width) << name;
    EXPECT_EQ(map.height, f.height) << name;
  }
  EXPECT_NE(vf::hazardMapFrame(dem).plotHeight, f.plotHeight);  // the whole grid would differ
  // A box off the DEM, or inverted: one error naming --extent, and no folder.
  for (const char* bad : {"0,0,10,10", "1050,5002,1010,5020"}) {
    r = runVoxfall(
        kExe, dir_,
        std::string("ensemble scene.toml --runs 4 --maps --extent ") + bad + " -q -o bad");
    EXPECT_EQ(r.code, 1) << bad;
    EXPECT_NE(r.err.find("--extent"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(dir_ / "bad")) << bad;
  }
}

// height_classes: every reached cell of height_classes.png has the colour of the class its
// height_p95 (read back from the GeoTIFF through GDAL) falls in; without the key, no such map.
TEST_F(EnsembleGeorefTest, HeightClassesMapShowsEachCellsClass) {
  vf::test::writeChuteScene(
      dir_, std::string(vf::test::kChuteEnsemble) + "height_classes = [0.2, 0.6]\n");
  const auto r = runVoxfall(
      kExe, dir_, "ensemble scene.toml --runs 4 --maps --extent 1010,5002,1050,5020 -q -o h");
  ASSERT_EQ(r.code, 0) << r.err;
  vf::Heightfield dem = vf::loadDem((dir_ / "chute.tif").string());
  vf::shiftHeightfield(dem, vf::Vec3(-1000, -5000, 0));
  const auto band = [&](const char* name) {
    GDALAllRegister();
    GDALDatasetH ds = GDALOpen((dir_ / "h" / name).c_str(), GA_ReadOnly);
    EXPECT_NE(ds, nullptr) << name;
    std::vector<double> v(static_cast<std::size_t>(dem.nx) * dem.ny);
    if (ds == nullptr) return v;
    int hasNoData = 0;
    GDALRasterBandH b = GDALGetRasterBand(ds, 1);
    const double noData = GDALGetRasterNoDataValue(b, &hasNoData);
    EXPECT_EQ(
        GDALRasterIO(b, GF_Read, 0, 0, dem.nx, dem.ny, v.data(), dem.nx, dem.ny, GDT_Float64, 0, 0),
        CE_None);
    GDALClose(ds);
    for (double& x : v)
      if (hasNoData && x == noData) x = std::nan("");
    return v;  // rows from the north
  };
  const std::vector<double> heights = band("height_p95.tif"), passages = band("passages.tif");
  const vf::MapClasses classes = vf::passingHeightClasses({0.2, 0.6});
  const vf::MapFrame f = vf::hazardMapFrame(dem, vf::extentWindow(dem, 1010, 5002, 1050, 5020));
  const vf::Image map = vf::readPng((dir_ / "h" / "height_classes.png").string());
  std::vector<int> seen(3, 0);
  for (int j = f.j0; j < f.j0 + f.nj; ++j)
    for (int i = f.i0; i < f.i0 + f.ni; ++i) {
      const std::size_t k = static_cast<std::size_t>(dem.ny - 1 - j) * dem.nx + i;
      if (!(passages[k] > 0)) continue;
      const int c = heights[k] < 0.2 ? 0 : heights[k] < 0.6 ? 1 : 2;
      ++seen[c];
      const int x = static_cast<int>(f.columnOf(dem.x0 + i * dem.cell));
      const int y = static_cast<int>(f.rowOf(dem.y0 + j * dem.cell));
      const std::uint8_t* p = map.pixel(x, y);
      EXPECT_EQ((vf::Rgb8{p[0], p[1], p[2]}), classes.colours[c])
          << "cell " << i << ", " << j << ": " << heights[k] << " m";
    }
  // The track crosses the window in more than one class, so a class mix-up shows.
  EXPECT_GE((seen[0] > 0) + (seen[1] > 0) + (seen[2] > 0), 2)
      << seen[0] << " " << seen[1] << " " << seen[2];
  vf::test::writeChuteScene(dir_, vf::test::kChuteEnsemble);
  const auto none = runVoxfall(kExe, dir_, "ensemble scene.toml --runs 2 --maps -q -o n");
  ASSERT_EQ(none.code, 0) << none.err;
  EXPECT_FALSE(fs::exists(dir_ / "n" / "height_classes.png"));
}

}  // namespace

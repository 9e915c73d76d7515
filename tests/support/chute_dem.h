// A small synthetic terrain for ensemble tests: a straight chute inclined 35 degrees, falling
// towards +x, written as a GeoTIFF with a CRS through GDAL, and a scene that releases rocks
// at its top. Tests stay short: level 2 rock, a few seconds of simulated time.
#pragma once

#include <cpl_conv.h>
#include <gdal.h>
#include <gtest/gtest.h>
#include <ogr_srs_api.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace vf::test {

struct ChuteDem {
  int nx = 60, ny = 12;
  double cell = 2.0;
  double west = 1000.0, north = 5024.0;  // outer corner of the north-west pixel, file coords
  double slopeDegrees = 35.0;
  double top = 100.0;    // height of the western column, m
  bool crs = true;       // false: a file that names no CRS
  int noDataCorner = 0;  // the k x k samples of the north-east corner are NODATA (-9999)
};

// Gives the dataset the CRS EPSG:<code>.
inline void setEpsg(GDALDatasetH ds, int code) {
  OGRSpatialReferenceH srs = OSRNewSpatialReference(nullptr);
  OSRImportFromEPSG(srs, code);
  char* wkt = nullptr;
  OSRExportToWkt(srs, &wkt);
  GDALSetProjection(ds, wkt);
  CPLFree(wkt);
  OSRDestroySpatialReference(srs);
}

// Writes the chute as a Float64 GeoTIFF in EPSG:31287 (MGI / Austria Lambert), or in no CRS;
// returns false if GDAL cannot.
inline bool writeChuteDem(const std::filesystem::path& path, const ChuteDem& c = {}) {
  GDALAllRegister();
  GDALDatasetH ds =
      GDALCreate(GDALGetDriverByName("GTiff"), path.c_str(), c.nx, c.ny, 1, GDT_Float64, nullptr);
  if (!ds) return false;
  double gt[6] = {c.west, c.cell, 0, c.north, 0, -c.cell};
  GDALSetGeoTransform(ds, gt);
  if (c.crs) setEpsg(ds, 31287);
  std::vector<double> z(static_cast<std::size_t>(c.nx) * c.ny);
  const double drop = std::tan(c.slopeDegrees * M_PI / 180.0) * c.cell;
  for (int row = 0; row < c.ny; ++row)
    for (int i = 0; i < c.nx; ++i)
      z[static_cast<std::size_t>(row) * c.nx + i] =
          row < c.noDataCorner && i >= c.nx - c.noDataCorner ? -9999.0 : c.top - drop * i;
  if (c.noDataCorner > 0) GDALSetRasterNoDataValue(GDALGetRasterBand(ds, 1), -9999.0);
  const bool ok = GDALRasterIO(GDALGetRasterBand(ds, 1), GF_Write, 0, 0, c.nx, c.ny, z.data(), c.nx,
                               c.ny, GDT_Float64, 0, 0) == CE_None;
  GDALClose(ds);
  return ok;
}

// A scene on chute.tif in `dir` whose [ensemble] table is `ensemble` (TOML lines), with
// `ground` (TOML lines) added to its [ground] table. World coordinates are the DEM's minus
// (1000, 5000): the chute spans x 0 .. 120, y 0 .. 24 in the world and x 1000 .. 1120,
// y 5000 .. 5024 in the DEM's coordinates, in which releases are written.
inline void writeChuteScene(const std::filesystem::path& dir, const std::string& ensemble,
                            double duration = 3.0, const std::string& ground = "") {
  std::ofstream f(dir / "scene.toml");
  f << "[simulation]\nduration = " << duration
    << "\nlevel = 2\nrotation = \"midpoint\"\n"
       "[ground]\nheightfield = \"chute.tif\"\noffset = [-1000.0, -5000.0, 0.0]\n"
       "material = \"glacial_deposits\"\n"
    << ground << "[shapes.rock]\nmesh = \"" << VOXFALL_SOURCE_DIR
    << "/scenes/meshes/rock.obj\"\nscale = 1.0\ndensity = 2600\n"
       "[ensemble]\n"
    << ensemble;
}

// The default release of the tests: a line across the chute's top, a push downhill.
inline const char* kChuteEnsemble =
    "shape = \"rock\"\n"
    "release = { line = [[1005.0, 5006.3], [1005.0, 5017.7]] }\n"
    "velocity = { min = [1.0, -0.5, 0.0], max = [3.0, 0.5, 0.0] }\n"
    "restitution = [0.3, 0.4]\n";

// A test in a fresh folder of its own holding chute.tif; the folder is removed after the test.
class ChuteFolderTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = std::filesystem::temp_directory_path() /
           ("voxfall_ensemble_test_" + std::to_string(::getpid()) + "_" + info->name());
    std::filesystem::remove_all(dir_);
    std::filesystem::create_directories(dir_);
    ASSERT_TRUE(writeChuteDem(dir_ / "chute.tif"));
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }

  std::filesystem::path dir_;
};

}  // namespace vf::test

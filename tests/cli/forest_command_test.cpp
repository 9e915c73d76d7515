// [forest] end to end on the synthetic chute (tests/support/chute_dem.h): an ensemble through a
// dense stand stops its rocks sooner than the same ensemble without one and writes the same bytes
// for any --jobs; a forest raster in another CRS stops `ensemble` and `simulate` with one line
// naming the file, and nothing is written.
#include <gdal.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "tests/support/chute_dem.h"
#include "tests/support/voxfall_command.h"

namespace {

namespace fs = std::filesystem;
using vf::test::readFile;
using vf::test::runVoxfall;

const std::string kExe = VOXFALL_EXE;

// The runout column of runs.csv, one value per realisation.
std::vector<double> runouts(const fs::path& runsCsv) {
  std::istringstream in(readFile(runsCsv));
  std::string line;
  std::getline(in, line);
  int column = 0;
  for (std::istringstream h(line); std::getline(h, line, ',') && line != "runout_m";) ++column;
  std::vector<double> out;
  while (std::getline(in, line)) {
    std::istringstream row(line);
    std::string field;
    for (int k = 0; k <= column; ++k) std::getline(row, field, ',');
    out.push_back(std::stod(field));
  }
  return out;
}

class ForestCommandTest : public vf::test::ChuteFolderTest {
 protected:
  void writeScene(const std::string& forest) {
    vf::test::writeChuteScene(dir_, vf::test::kChuteEnsemble, 3.0);
    if (!forest.empty())
      std::ofstream(dir_ / "scene.toml", std::ios::app) << "[forest]\n" << forest;
  }
};

}  // namespace

// The chute's rocks (0.034 m^3, 88 kg, a 0.40 m sphere's volume) run down 35 degrees for 3 s.
// 3000 stems/ha of 40 cm (192 kJ a stem, more than any rock here carries: 88 kg at 30 m/s is
// 40 kJ) give a mean free path of 1 / (0.3 * 0.8) = 4.2 m: every rock is stopped within metres,
// where without trees it runs on.
TEST_F(ForestCommandTest, ADenseStandShortensEveryRunoutAndKeepsTheBytesForAnyJobs) {
  writeScene("");
  ASSERT_EQ(runVoxfall(kExe, dir_, "ensemble scene.toml --runs 6 -q -o bare").code, 0);
  writeScene("density = 3000\ndbh = 40\n");
  const auto one = runVoxfall(kExe, dir_, "ensemble scene.toml --runs 6 --jobs 1 -q -o f1");
  ASSERT_EQ(one.code, 0) << one.err;
  ASSERT_EQ(runVoxfall(kExe, dir_, "ensemble scene.toml --runs 6 --jobs 2 -q -o f2").code, 0);
  EXPECT_EQ(readFile(dir_ / "f1" / "runs.csv"), readFile(dir_ / "f2" / "runs.csv"));
  EXPECT_EQ(readFile(dir_ / "f1" / "reach_probability.tif"),
            readFile(dir_ / "f2" / "reach_probability.tif"));
  const auto bare = runouts(dir_ / "bare" / "runs.csv"), forest = runouts(dir_ / "f1" / "runs.csv");
  ASSERT_EQ(bare.size(), 6u);
  ASSERT_EQ(forest.size(), 6u);
  for (std::size_t k = 0; k < bare.size(); ++k)
    EXPECT_LT(forest[k], bare[k]) << "realisation " << k;
}

TEST_F(ForestCommandTest, ARasterInAnotherCrsStopsTheRunAndWritesNothing) {
  // The chute's own grid, written in UTM 32N instead of the DEM's Austria Lambert.
  GDALAllRegister();
  const fs::path raster = dir_ / "stems.tif";
  GDALDatasetH ds =
      GDALCreate(GDALGetDriverByName("GTiff"), raster.c_str(), 60, 12, 1, GDT_Float64, nullptr);
  ASSERT_NE(ds, nullptr);
  double gt[6] = {1000, 2, 0, 5024, 0, -2};
  GDALSetGeoTransform(ds, gt);
  vf::test::setEpsg(ds, 32632);
  GDALClose(ds);
  writeScene("density = \"stems.tif\"\ndbh = 30\n");
  for (const std::string command :
       {"ensemble scene.toml --runs 2 -q -o out", "simulate scene.toml -q --outcomes out.csv"}) {
    const auto r = runVoxfall(kExe, dir_, command);
    EXPECT_EQ(r.code, 1) << command;
    // The file as the scene names it (relative to the scene's folder, here the working one).
    EXPECT_NE(r.err.find("stems.tif: stem density raster is in EPSG:32632, the DEM in EPSG:31287"),
              std::string::npos)
        << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  }
  EXPECT_FALSE(fs::exists(dir_ / "out"));
  EXPECT_FALSE(fs::exists(dir_ / "out.csv"));
}

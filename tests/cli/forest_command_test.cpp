// [forest] end to end on the synthetic chute (tests/support/chute_dem.h): an ensemble through a
// dense stand stops its rocks sooner than the same ensemble without one and writes the same bytes
// for any --jobs; runs.csv's tree impacts are those of each realisation's world stepped here on
// its own, and the same after two shards merged; a forest raster in another CRS stops `ensemble`
// and `simulate` with one line naming the file, and nothing is written.
#include <gdal.h>
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "sim/ensemble/ensemble.h"
#include "sim/scene/scene.h"
#include "tests/support/chute_dem.h"
#include "tests/support/voxfall_command.h"

namespace {

namespace fs = std::filesystem;
using vf::test::readFile;
using vf::test::runVoxfall;

const std::string kExe = VOXFALL_EXE;

// runs.csv as rows of column name -> text.
std::vector<std::map<std::string, std::string>> runsTable(const fs::path& runsCsv) {
  std::istringstream in(readFile(runsCsv));
  std::string line, field;
  std::getline(in, line);
  std::vector<std::string> names;
  for (std::istringstream h(line); std::getline(h, field, ',');) names.push_back(field);
  std::vector<std::map<std::string, std::string>> out;
  while (std::getline(in, line)) {
    std::istringstream row(line);
    out.emplace_back();
    for (std::size_t k = 0; k < names.size() && std::getline(row, field, ','); ++k)
      out.back()[names[k]] = field;
  }
  return out;
}

// The runout column of runs.csv, one value per realisation.
std::vector<double> runouts(const fs::path& runsCsv) {
  std::vector<double> out;
  for (const auto& row : runsTable(runsCsv)) out.push_back(std::stod(row.at("runout_m")));
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

// 800 stems/ha of 20 cm: a mean free path of 1 / (0.08 * (0.2 + 0.4)) = 21 m on the chute, so
// some rocks meet stems within 3 s and are not all stopped by the first. The oracle is the
// realisation's World from Ensemble::makeWorld, stepped here as a rock-fall run ends (the
// duration, or the rock stopped, left or buried), and its RockFall's treeHits of the rock.
TEST_F(ForestCommandTest, TreeColumnsAreThoseOfEachRealisationRunOnItsOwn) {
  writeScene("");
  ASSERT_EQ(runVoxfall(kExe, dir_, "ensemble scene.toml --runs 3 --seed 5 -q -o bare").code, 0);
  for (const auto& row : runsTable(dir_ / "bare" / "runs.csv")) {
    EXPECT_EQ(row.at("tree_hits"), "0");
    EXPECT_EQ(row.at("tree_energy_kJ"), "0.0000");
  }
  writeScene("density = 800\ndbh = 20\n");
  const auto run = runVoxfall(kExe, dir_, "ensemble scene.toml --runs 8 --seed 5 -q -o f");
  ASSERT_EQ(run.code, 0) << run.err;
  const auto rows = runsTable(dir_ / "f" / "runs.csv");
  ASSERT_EQ(rows.size(), 8u);
  const vf::SceneSpec spec = vf::loadScene((dir_ / "scene.toml").string());
  const vf::Ensemble ensemble(spec);
  int hit = 0;
  for (std::size_t k = 0; k < rows.size(); ++k) {
    const std::uint64_t seed = vf::realisationSeed(5, static_cast<std::int64_t>(k));
    ASSERT_EQ(rows[k].at("seed"), std::to_string(seed));
    const vf::RealisationWorld made = ensemble.makeWorld(seed);
    vf::World& w = *made.world;
    while (w.nextStepEnd() <= spec.duration + vf::kTimeTolerance) {
      w.stepNext();
      if (made.rockFall->outcomes()[0].state != vf::RockState::kMoving) break;
    }
    char hex[17], kJ[64];
    std::snprintf(hex, sizeof hex, "%016llx", static_cast<unsigned long long>(w.stepsHash()));
    ASSERT_EQ(rows[k].at("checksum"), hex) << "realisation " << k << " is another run";
    const vf::TreeHits trees = made.rockFall->treeHits(0);
    std::snprintf(kJ, sizeof kJ, "%.4f", trees.absorbed / 1000.0);
    EXPECT_EQ(rows[k].at("tree_hits"), std::to_string(trees.hits)) << "realisation " << k;
    EXPECT_EQ(rows[k].at("tree_energy_kJ"), kJ) << "realisation " << k;
    hit += trees.hits > 0 ? 1 : 0;
  }
  EXPECT_GE(hit, 1) << "no realisation met a stem: the stand tests nothing";
  // Through the journal: two shards merged write the same runs.csv.
  ASSERT_EQ(
      runVoxfall(kExe, dir_, "ensemble scene.toml --runs 8 --seed 5 --shard 0/2 -q -o s0").code, 0);
  ASSERT_EQ(
      runVoxfall(kExe, dir_, "ensemble scene.toml --runs 8 --seed 5 --shard 1/2 -q -o s1").code, 0);
  ASSERT_EQ(runVoxfall(kExe, dir_, "ensemble-merge s0 s1 -q -o merged").code, 0);
  EXPECT_EQ(readFile(dir_ / "merged" / "runs.csv"), readFile(dir_ / "f" / "runs.csv"));
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

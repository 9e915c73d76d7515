// Evaluation lines end to end on the straight synthetic chute (tests/support/chute_dem.h).
// The oracle is an independent computation from the trajectory CSV: with a fixed step equal to
// the frame interval every frame is a step state, so the crossings of the centre of mass found
// from consecutive rows (by the sign of each row's side of the line, not by the recorder's
// segment intersection), their interpolated time, energies (the cube's inertia m a^2 / 6 from
// its side, not the simulator's) and the height above the chute's analytic plane must be what
// `simulate --lines` wrote. Ensembles: the same files for any --jobs and after a merge of
// shards. Bad inputs: one error naming the file and what is wrong, nothing written.
#include <gtest/gtest.h>

#include <cmath>
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

constexpr double kSide = 0.6, kDensity = 2600;  // the cube: scenes/meshes/cube.obj scaled
constexpr double kMass = kDensity * kSide * kSide * kSide;
constexpr double kInertia = kMass * kSide * kSide / 6;  // a cube's, about any axis
constexpr double kStep = 0.002;                         // s: the fixed step and 1 / fps

// The lines of the test, DEM file coordinates: across the chute, and slanted.
struct TestLine {
  double x0, y0, x1, y1;
};
const TestLine kLines[] = {{1010.0, 5001.0, 1010.0, 5023.0}, {1014.0, 5001.0, 1018.0, 5023.0}};

std::vector<std::vector<double>> readCsv(const fs::path& path, std::string* header = nullptr) {
  std::ifstream in(path);
  std::string line;
  std::getline(in, line);
  if (header) *header = line;
  std::vector<std::vector<double>> rows;
  while (std::getline(in, line)) {
    std::vector<double> row;
    std::istringstream s(line);
    for (std::string f; std::getline(s, f, ',');)
      row.push_back(f.empty() ? NAN : f[0] == '"' ? 0.0 : std::stod(f));
    rows.push_back(row);
  }
  return rows;
}

class EvaluationLinesTest : public vf::test::ChuteFolderTest {
 protected:
  // A cube pushed down the chute, stepped at `kStep`, with frames every `frameInterval`.
  void writeScene(double frameInterval, const std::string& lines) {
    std::ofstream f(dir_ / "scene.toml");
    f << "[simulation]\nduration = 4.0\nlevel = 2\nstep = " << kStep
      << "\nfps = " << 1 / frameInterval
      << "\n[ground]\nheightfield = \"chute.tif\"\noffset = [-1000.0, -5000.0, 0.0]\n"
         "material = \"glacial_deposits\"\n[shapes.cube]\nmesh = \""
      << VOXFALL_SOURCE_DIR << "/scenes/meshes/cube.obj\"\nscale = " << kSide
      << "\ndensity = " << kDensity
      << "\n[[bodies]]\nshape = \"cube\"\nposition = [4.0, 12.0, 98.0]\n"
         "velocity = [6.0, 0.4, 0.0]\nangular_velocity = [0.0, 3.0, 0.0]\ndrop_height = 0.3\n"
      << lines;
  }
  static std::string sceneLines() {
    std::ostringstream s;
    const char* names[] = {"across", "slanted"};
    for (int l = 0; l < 2; ++l)
      s << "[[evaluation_lines]]\nname = \"" << names[l] << "\"\npoints = [[" << kLines[l].x0
        << ", " << kLines[l].y0 << "], [" << kLines[l].x1 << ", " << kLines[l].y1 << "]]\n";
    return s.str();
  }
};

// The chute's surface under file x: sample i (centre x = 1001 + 2 i) is 100 - tan(35 deg) 2 i.
double chuteHeight(double fileX) {
  return 100.0 - std::tan(35.0 * M_PI / 180.0) * (fileX - 1001.0);
}

TEST_F(EvaluationLinesTest, CrossingsMatchAnIndependentComputationFromTheTrajectoryCsv) {
  writeScene(kStep, sceneLines());
  const auto r = runVoxfall(kExe, dir_, "simulate scene.toml --csv run.csv --lines lines -q");
  ASSERT_EQ(r.code, 0) << r.err;
  const auto frames = readCsv(dir_ / "run.csv");
  const auto got = readCsv(dir_ / "lines" / "crossings.csv");

  // Independent crossings: the signed side of each row's centre (file coordinates) changes
  // sign between consecutive rows, at the fraction s = f0 / (f0 - f1) of the step.
  struct Expected {
    int line;
    double time, x, y, z, translational, rotational, height;
  };
  std::vector<Expected> want;
  for (std::size_t k = 1; k < frames.size(); ++k) {
    const auto& a = frames[k - 1];
    const auto& b = frames[k];
    for (int l = 0; l < 2; ++l) {
      const TestLine& L = kLines[l];
      const auto side = [&](const std::vector<double>& row) {
        return (L.x1 - L.x0) * (row[4] + 5000 - L.y0) - (L.y1 - L.y0) * (row[3] + 1000 - L.x0);
      };
      const double f0 = side(a), f1 = side(b);
      if (!((f0 > 0 && f1 <= 0) || (f0 < 0 && f1 >= 0))) continue;
      const double s = f0 / (f0 - f1);
      const auto at = [&](int col) { return a[col] + s * (b[col] - a[col]); };
      const double x = at(3) + 1000, y = at(4) + 5000;
      const double u = ((x - L.x0) * (L.x1 - L.x0) + (y - L.y0) * (L.y1 - L.y0)) /
                       ((L.x1 - L.x0) * (L.x1 - L.x0) + (L.y1 - L.y0) * (L.y1 - L.y0));
      if (u < 0 || u > 1) continue;
      const double vx = at(10), vy = at(11), vz = at(12);
      const auto spin = [](const std::vector<double>& row) {
        return 0.5 * kInertia * (row[13] * row[13] + row[14] * row[14] + row[15] * row[15]);
      };
      want.push_back({l, at(1), x, y, at(5), 0.5 * kMass * (vx * vx + vy * vy + vz * vz),
                      spin(a) + s * (spin(b) - spin(a)), at(5) - chuteHeight(x)});
    }
  }
  ASSERT_EQ(want.size(), 2u) << "the cube should cross each line once";
  ASSERT_EQ(got.size(), want.size());
  for (std::size_t c = 0; c < want.size(); ++c) {
    const auto& g = got[c];
    const Expected& w = want[c];
    EXPECT_EQ(g[0], w.line);
    // Frames and step states agree to the free motion over the last bits of the time
    // (|t - k dt| ~ 1e-15 s), so the numbers agree to well under 1e-9.
    EXPECT_NEAR(g[3], w.time, 1e-9);
    EXPECT_NEAR(g[4], w.x, 1e-9);
    EXPECT_NEAR(g[5], w.y, 1e-9);
    EXPECT_NEAR(g[6], w.z, 1e-9);
    EXPECT_NEAR(g[11] * 1000, w.translational, 1e-9 * w.translational);
    EXPECT_NEAR(g[12] * 1000, w.rotational, 1e-9 * w.rotational);
    EXPECT_NEAR(g[14], w.height, 1e-9);
    EXPECT_EQ(g[15], 1) << "the cube runs from the lines' left to their right";
  }
  // The summary: one rock, crossing each line once: every percentile is that crossing.
  const auto summary = readCsv(dir_ / "lines" / "lines.csv");
  ASSERT_EQ(summary.size(), 2u);
  for (int l = 0; l < 2; ++l) {
    EXPECT_EQ(summary[l][2], 1);  // crossings
    EXPECT_EQ(summary[l][5], 1);  // probability
    for (int p = 0; p < 3; ++p) {
      EXPECT_DOUBLE_EQ(summary[l][6 + p], got[l][13]);
      EXPECT_DOUBLE_EQ(summary[l][9 + p], got[l][14]);
    }
  }
  EXPECT_TRUE(fs::exists(dir_ / "lines" / "lines.png"));
  EXPECT_TRUE(fs::exists(dir_ / "lines" / "lines_profile.png"));
}

TEST_F(EvaluationLinesTest, CrossingsDoNotDependOnTheFrameRate) {
  writeScene(kStep, sceneLines());
  ASSERT_EQ(runVoxfall(kExe, dir_, "simulate scene.toml --lines fine -q").code, 0);
  writeScene(0.1, sceneLines());
  ASSERT_EQ(runVoxfall(kExe, dir_, "simulate scene.toml --lines coarse -q").code, 0);
  EXPECT_EQ(readFile(dir_ / "fine" / "crossings.csv"), readFile(dir_ / "coarse" / "crossings.csv"));
}

TEST_F(EvaluationLinesTest, EnsembleLinesAreTheSameForAnyJobsAndAfterAMerge) {
  vf::test::writeChuteScene(dir_, vf::test::kChuteEnsemble);
  std::ofstream(dir_ / "scene.toml", std::ios::app)
      << "[[evaluation_lines]]\nname = \"fence\"\npoints = [[1012.0, 5001.0], [1012.0, 5023.0]]\n";
  const std::string common = "ensemble scene.toml --runs 8 --seed 3 -q";
  ASSERT_EQ(runVoxfall(kExe, dir_, common + " --jobs 1 -o j1").code, 0);
  ASSERT_EQ(runVoxfall(kExe, dir_, common + " --jobs 2 -o j2").code, 0);
  ASSERT_EQ(runVoxfall(kExe, dir_, common + " --shard 0/2 -o s0").code, 0);
  ASSERT_EQ(runVoxfall(kExe, dir_, common + " --shard 1/2 -o s1").code, 0);
  ASSERT_EQ(runVoxfall(kExe, dir_, "ensemble-merge s0 s1 -q -o merged").code, 0);
  for (const char* name : {"crossings.csv", "lines.csv"}) {
    const std::string one = readFile(dir_ / "j1" / name);
    ASSERT_FALSE(one.empty()) << name;
    EXPECT_EQ(one, readFile(dir_ / "j2" / name)) << name;
    EXPECT_EQ(one, readFile(dir_ / "merged" / name)) << name;
  }
  // The probability is the share of realisations in crossings.csv.
  const auto crossings = readCsv(dir_ / "j1" / "crossings.csv");
  std::vector<double> rocks;
  for (const auto& c : crossings)
    if (std::find(rocks.begin(), rocks.end(), c[2]) == rocks.end()) rocks.push_back(c[2]);
  const auto summary = readCsv(dir_ / "j1" / "lines.csv");
  EXPECT_GT(rocks.size(), 0u);
  EXPECT_EQ(summary[0][2], static_cast<double>(crossings.size()));
  EXPECT_EQ(summary[0][3], static_cast<double>(rocks.size()));
  EXPECT_DOUBLE_EQ(summary[0][5], rocks.size() / 8.0);
}

// Each bad line: exit 1, one line on stderr naming the file and the problem, nothing written.
TEST_F(EvaluationLinesTest, BadLinesAreOneErrorAndWriteNothing) {
  std::ofstream(dir_ / "wgs84.geojson")
      << R"({"type": "FeatureCollection", "crs": {"type": "name", "properties": {"name":
        "urn:ogc:def:crs:EPSG::4326"}}, "features": [{"type": "Feature", "properties": {},
        "geometry": {"type": "LineString", "coordinates": [[1010, 5001], [1010, 5023]]}}]})";
  std::ofstream(dir_ / "austria.geojson")
      << R"({"type": "FeatureCollection", "features": [{"type": "Feature", "properties": {},
        "geometry": {"type": "LineString", "coordinates": [[14.0, 47.5], [14.001, 47.5]]}}]})";
  std::ofstream(dir_ / "nocrs.csv") << "WKT,id\n\"LINESTRING (1010 5001,1010 5023)\",1\n";
  const std::string table = "[[evaluation_lines]]\nname = \"bad\"\n";
  const std::pair<std::string, std::string> cases[] = {
      {"points = [[1010.0, 5001.0], [1500.0, 5023.0]]\n",
       "scene.toml:22:29: evaluation line 'bad' point 1 (1500.000, 5023.000) lies outside the DEM"},
      {"file = \"missing.gpkg\"\n", "scene.toml:22:8: vector file not found: 'missing.gpkg'"},
      // Coordinates of the DEM's CRS in a file that says WGS84: no such place, or far off.
      {"file = \"wgs84.geojson\"\n",
       "wgs84.geojson: feature 0 cannot be transformed to the DEM's coordinate reference system"},
      {"file = \"austria.geojson\"\n", "austria.geojson: feature 0: evaluation line 'bad' point 0"},
      {"file = \"nocrs.csv\"\n", "names no coordinate reference system"},
      {"points = [[1010.0, 5001.0]]\n", "'points' must be an array of at least 2"},
  };
  for (const auto& [key, message] : cases) {
    writeScene(kStep, table + key);
    const auto r = runVoxfall(kExe, dir_, "simulate scene.toml --lines out --csv out/run.csv -q");
    EXPECT_EQ(r.code, 1) << key;
    EXPECT_NE(r.err.find(message), std::string::npos) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_TRUE(!fs::exists(dir_ / "out") || fs::is_empty(dir_ / "out")) << key;
  }
}

}  // namespace

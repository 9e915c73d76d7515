// Barriers end to end on the straight synthetic chute (tests/support/chute_dem.h): a rock pushed
// down the chute is stopped by a barrier whose capacity exceeds its energy, and breaks through
// one whose capacity does not, which an evaluation line beyond the barrier sees; bad barriers
// are one error naming the file and what is wrong, with nothing written.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "tests/support/chute_dem.h"
#include "tests/support/voxfall_command.h"

namespace {

namespace fs = std::filesystem;
using vf::test::readFile;
using vf::test::runVoxfall;

const std::string kExe = VOXFALL_EXE;

class BarriersCommandTest : public vf::test::ChuteFolderTest {
 protected:
  void writeScene(const std::string& barrier) {
    std::ofstream f(dir_ / "scene.toml");
    f << "[simulation]\nduration = 6.0\nlevel = 2\nstop = \"all_at_rest\"\n"
         "[ground]\nheightfield = \"chute.tif\"\noffset = [-1000.0, -5000.0, 0.0]\n"
         "material = \"glacial_deposits\"\n[shapes.rock]\nmesh = \""
      << VOXFALL_SOURCE_DIR
      << "/scenes/meshes/rock.obj\"\ndensity = 2600\n"
         "[[bodies]]\nshape = \"rock\"\nposition = [4.0, 12.0, 98.0]\n"
         "velocity = [4.0, 0.0, 0.0]\ndrop_height = 0.3\n"
         "[[evaluation_lines]]\nname = \"beyond\"\npoints = [[1016.0, 5001.0], [1016.0, 5023.0]]\n"
         "[[barriers]]\nname = \"net\"\n"
      << barrier;
  }
};

TEST_F(BarriersCommandTest, UnderTheCapacityTheRockStopsOverItItBreaksThrough) {
  const std::string at = "points = [[1012.0, 5001.0], [1012.0, 5023.0]]\nheight = 3.0\n";
  writeScene(at + "capacity = 500.0\n");
  const auto held =
      runVoxfall(kExe, dir_, "simulate scene.toml --barriers held.csv --lines held -q");
  ASSERT_EQ(held.code, 0) << held.err;
  EXPECT_EQ(readFile(dir_ / "held.csv").substr(0, 66),
            "barrier,name,capacity_kj,hits,stopped,passed,max_energy_kj,failed\n");
  EXPECT_NE(readFile(dir_ / "held.csv").find("0,\"net\",500,1,1,0,"), std::string::npos)
      << readFile(dir_ / "held.csv");
  EXPECT_NE(readFile(dir_ / "held" / "lines.csv").find("0,\"beyond\",0,0,1,0,"), std::string::npos);

  writeScene(at + "capacity = 0.05\n");
  const auto broke =
      runVoxfall(kExe, dir_, "simulate scene.toml --barriers broke.csv --lines broke -q");
  ASSERT_EQ(broke.code, 0) << broke.err;
  // The capacity as the scene gives it: the shortest text of the same double.
  EXPECT_NE(readFile(dir_ / "broke.csv").find("0,\"net\",0.05,1,0,1,"), std::string::npos)
      << readFile(dir_ / "broke.csv");
  EXPECT_NE(readFile(dir_ / "broke" / "lines.csv").find("0,\"beyond\",1,1,1,1,"), std::string::npos)
      << readFile(dir_ / "broke" / "lines.csv");
}

TEST_F(BarriersCommandTest, BadBarriersAreOneErrorAndWriteNothing) {
  const std::string at = "points = [[1012.0, 5001.0], [1012.0, 5023.0]]\n";
  const std::pair<std::string, std::string> cases[] = {
      {at + "height = 3.0\ncapacity = -5.0\n",
       "scene.toml:24:12: 'capacity' must be >= 0 kJ, got -5"},
      {at + "capacity = 5.0\n", "scene.toml:20:1: missing required key 'height' in [[barriers]]"},
      {"points = [[1012.0, 5001.0], [1012.0, 5090.0]]\nheight = 3.0\ncapacity = 5.0\n",
       "scene.toml:22:29: barrier 'net' point 1 (1012.000, 5090.000) lies outside the DEM"},
      {"file = \"nets.gpkg\"\nheight = 3.0\ncapacity = 5.0\n",
       "scene.toml:22:8: vector file not found: 'nets.gpkg'"},
  };
  for (const auto& [table, message] : cases) {
    writeScene(table);
    const auto r = runVoxfall(kExe, dir_, "simulate scene.toml --barriers out/b.csv -q");
    EXPECT_EQ(r.code, 1) << table;
    EXPECT_NE(r.err.find(message), std::string::npos) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_TRUE(!fs::exists(dir_ / "out") || fs::is_empty(dir_ / "out")) << table;
  }
}

// Two nets from one GeoJSON file (EPSG:31287, the chute's CRS), each with its own height and
// capacity from the feature's attributes: the first (0.05 kJ) breaks, the second (500 kJ) holds.
void writeNets(const fs::path& path, const std::string& second) {
  std::ofstream(path)
      << R"({"type": "FeatureCollection", "crs": {"type": "name", "properties": {"name":
        "urn:ogc:def:crs:EPSG::31287"}}, "features": [
        {"type": "Feature", "properties": {"h": 3.0, "cap": 0.05}, "geometry":
          {"type": "LineString", "coordinates": [[1010, 5001], [1010, 5023]]}},
        {"type": "Feature", "properties": )"
      << second << R"(, "geometry":
          {"type": "LineString", "coordinates": [[1014, 5001], [1014, 5023]]}}]})";
}

TEST_F(BarriersCommandTest, EachFeatureOfAFileHasItsOwnHeightAndCapacity) {
  writeNets(dir_ / "nets.geojson", R"({"h": 3.0, "cap": 500.0})");
  writeScene("file = \"nets.geojson\"\nheight_field = \"h\"\ncapacity_field = \"cap\"\n");
  const auto r = runVoxfall(kExe, dir_, "simulate scene.toml --barriers nets.csv -q");
  ASSERT_EQ(r.code, 0) << r.err;
  const std::string csv = readFile(dir_ / "nets.csv");
  // The shortest text of each number, as every number of the CSV.
  EXPECT_NE(csv.find("0,\"net#0\",0.05,1,0,1,"), std::string::npos) << csv;
  EXPECT_NE(csv.find("1,\"net#1\",500,1,1,0,"), std::string::npos) << csv;

  const std::string fields = "height_field = \"h\"\ncapacity_field = \"cap\"\n";
  const std::pair<std::string, std::string> cases[] = {
      {R"({"h": 3.0})",
       "nets.geojson: feature 1: barrier 'net#1' has no number in field 'cap' (its capacity, kJ)"},
      {R"({"h": 3.0, "cap": -2.0})",
       "nets.geojson: feature 1: barrier 'net#1': 'cap' (its capacity, kJ) must be >= 0, got -2"},
      {R"({"h": 0.0, "cap": 5.0})",
       "nets.geojson: feature 1: barrier 'net#1': 'h' (its height, m) must be > 0, got 0"},
  };
  for (const auto& [props, message] : cases) {
    writeNets(dir_ / "nets.geojson", props);
    writeScene("file = \"nets.geojson\"\n" + fields);
    const auto bad = runVoxfall(kExe, dir_, "simulate scene.toml --barriers out/b.csv -q");
    EXPECT_EQ(bad.code, 1) << props;
    EXPECT_NE(bad.err.find(message), std::string::npos) << bad.err;
    EXPECT_EQ(std::count(bad.err.begin(), bad.err.end(), '\n'), 1) << bad.err;
    EXPECT_TRUE(!fs::exists(dir_ / "out") || fs::is_empty(dir_ / "out")) << props;
  }
  const std::pair<std::string, std::string> tables[] = {
      {"points = [[1012.0, 5001.0], [1012.0, 5023.0]]\n" + fields,
       "scene.toml:23:16: 'height_field' needs 'file' (a vector file of lines)"},
      {"file = \"nets.geojson\"\nheight = 3.0\n" + fields,
       "scene.toml:23:10: give either 'height' or 'height_field', not both"},
  };
  for (const auto& [table, message] : tables) {
    writeScene(table);
    const auto bad = runVoxfall(kExe, dir_, "simulate scene.toml --barriers out/b.csv -q");
    EXPECT_EQ(bad.code, 1) << table;
    EXPECT_NE(bad.err.find(message), std::string::npos) << bad.err;
  }
}

}  // namespace

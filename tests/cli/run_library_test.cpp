// The run library (render/run/) called without argv writes the same bytes as the voxfall
// command: `simulate`, `render` and `ensemble` on small scenes, each run once through the
// library and once through the built binary in the same folder with the same paths. The only
// bytes allowed to differ are the wall-clock seconds a summary records.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <string>

#include "render/run/ensemble_run.h"
#include "render/run/render_run.h"
#include "render/run/simulate_run.h"
#include "tests/support/chute_dem.h"
#include "tests/support/voxfall_command.h"

namespace {

namespace fs = std::filesystem;
using vf::test::readFile;
using vf::test::runVoxfall;

const std::string kExe = VOXFALL_EXE;

// The file's bytes with the run's wall-clock time (summary JSON, bake header) blanked.
std::string withoutWallTime(const fs::path& path) {
  static const std::regex wall("\"wall_seconds\": ?[-+.0-9eE]+");
  return std::regex_replace(readFile(path), wall, "\"wall_seconds\": 0");
}

// Every file under `folder`, by path relative to it, with its bytes.
std::map<std::string, std::string> filesUnder(const fs::path& folder) {
  std::map<std::string, std::string> out;
  for (const auto& e : fs::recursive_directory_iterator(folder))
    if (e.is_regular_file()) out[fs::relative(e.path(), folder).string()] = readFile(e.path());
  return out;
}

// A scratch folder that is also the working directory while the test runs, so that the
// library call and the command see the same relative paths (summaries record them).
class RunLibrary : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = vf::test::scratchFolder("voxfall_run_library", info->name());
    fs::create_directories(dir_ / "meshes");
    const fs::path scenes = fs::path(VOXFALL_SOURCE_DIR) / "scenes";
    fs::copy_file(scenes / "meshes/cube.obj", dir_ / "meshes/cube.obj");
    const std::string text = readFile(scenes / "cubes.toml");
    // One second of the paper's cubes: enough frames to compare, short enough to run twice.
    std::ofstream(dir_ / "cubes.toml")
        << std::regex_replace(text, std::regex("duration = 2\\.0"), "duration = 1.0");
    ASSERT_NE(readFile(dir_ / "cubes.toml"), text) << "cubes.toml's duration line changed";
    home_ = fs::current_path();
    fs::current_path(dir_);
  }
  void TearDown() override {
    fs::current_path(home_);
    fs::remove_all(dir_);
  }

  fs::path dir_, home_;
};

TEST_F(RunLibrary, SimulateWritesTheCommandsBytes) {
  vf::SimulateRequest r;
  r.scene = "cubes.toml";
  r.csv = "lib/run.csv";
  r.summary = "lib/run.json";
  r.bake = "lib/run.bake";
  r.quiet = true;
  ASSERT_TRUE(vf::runSimulation(r).isDone());
  const auto cli = runVoxfall(
      kExe, dir_,
      "simulate cubes.toml --csv cli/run.csv --summary cli/run.json --bake cli/run.bake -q");
  ASSERT_EQ(cli.code, 0) << cli.err;
  EXPECT_GT(readFile(dir_ / "cli/run.csv").size(), 1000u);
  EXPECT_TRUE(readFile(dir_ / "lib/run.csv") == readFile(dir_ / "cli/run.csv"));
  for (const char* name : {"run.json", "run.bake"})
    EXPECT_TRUE(withoutWallTime(dir_ / "lib" / name) == withoutWallTime(dir_ / "cli" / name))
        << name;
}

TEST_F(RunLibrary, RenderWritesTheCommandsFrames) {
  vf::RenderRequest r;
  r.input = "cubes.toml";
  r.output = "lib/frame_####.png";
  r.frames = "10:12";
  r.drawing.size = std::make_pair(96, 72);
  r.quiet = true;
  ASSERT_TRUE(vf::runRender(r).isDone());
  const auto cli = runVoxfall(
      kExe, dir_, "render cubes.toml -o cli/frame_####.png --frames 10:12 --size 96x72 -q");
  ASSERT_EQ(cli.code, 0) << cli.err;
  const auto lib = filesUnder(dir_ / "lib");
  EXPECT_EQ(lib.size(), 3u);
  EXPECT_TRUE(lib.count("frame_0011.png"));
  EXPECT_TRUE(lib == filesUnder(dir_ / "cli"));
}

TEST_F(RunLibrary, EnsembleWritesTheCommandsBytes) {
  ASSERT_TRUE(vf::test::writeChuteDem(dir_ / "chute.tif"));
  vf::test::writeChuteScene(dir_, vf::test::kChuteEnsemble);
  vf::EnsembleRequest r;
  r.scene = "scene.toml";
  r.runs = 6;
  r.jobs = 2;
  r.files.outDir = "lib";
  r.files.converge = true;
  r.files.quiet = true;
  ASSERT_TRUE(vf::runEnsemble(r).isDone());
  const auto cli =
      runVoxfall(kExe, dir_, "ensemble scene.toml --runs 6 --jobs 2 --converge -q -o cli");
  ASSERT_EQ(cli.code, 0) << cli.err;
  auto lib = filesUnder(dir_ / "lib"), ref = filesUnder(dir_ / "cli");
  EXPECT_TRUE(lib.count("runs.csv") && lib.count("summary.json") && lib.count("converge.csv"));
  // The journal holds the realisations in the order they completed, which threads vary.
  ASSERT_TRUE(lib.erase("ensemble.journal") && ref.erase("ensemble.journal"));
  EXPECT_EQ(lib.size(), ref.size());
  for (const auto& [name, bytes] : ref) EXPECT_TRUE(lib[name] == bytes) << name;
}

}  // namespace

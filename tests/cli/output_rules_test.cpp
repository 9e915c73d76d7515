// One way to write output and one way to stop, with real child processes:
// SIGTERM and SIGINT during `simulate` and `render` leave a valid CSV and summary / a playable
// MP4 up to the last complete frame and exit 143 / 130; an existing output is refused without
// -y (and kept with -n), an input of the run is never overwritten, and output folders are
// created by every command.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <functional>
#include <nlohmann/json.hpp>
#include <regex>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "tests/support/voxfall_command.h"

namespace {

namespace fs = std::filesystem;
using vf::test::readFile;

// Temporary output files (".NAME.partial-PID-N.EXT") in `folder`, and their total size.
std::uintmax_t partialBytes(const fs::path& folder, int* count = nullptr) {
  std::uintmax_t bytes = 0;
  int n = 0;
  for (const auto& e : fs::directory_iterator(folder))
    if (e.path().filename().string().find(".partial-") != std::string::npos) {
      bytes += e.file_size();
      ++n;
    }
  if (count) *count = n;
  return bytes;
}

class OutputRules : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() /
           ("voxfall_output_rules_" + std::to_string(::getpid()) + "_" + info->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    // cubes.toml with a chosen duration, its mesh beside it (an input of the run).
    // Runs long enough that a signal lands mid-run: `simulate` of 600 s, and `render` of 30 s
    // (simulated whole before its 901 frames are drawn).
    vf::test::copyCubesScene(fs::path(VOXFALL_SOURCE_DIR) / "scenes", dir_,
                             {{"long.toml", 600}, {"minute.toml", 30}});
  }
  void TearDown() override { fs::remove_all(dir_); }

  int run(const std::string& args) {
    const vf::test::CommandResult r = vf::test::runVoxfall(VOXFALL_EXE, dir_, args + " --quiet");
    err_ = r.err;
    return r.code;
  }

  // Starts `voxfall ARGS...` in dir_, waits until `ready()` says frames are flowing, sends
  // `sig` and returns the exit status.
  int interrupt(const std::vector<std::string>& args, int sig, const std::function<bool()>& ready) {
    fs::remove(dir_ / "stderr.txt");  // ready() must not read an earlier run's
    const int status =
        vf::test::interruptVoxfall(VOXFALL_EXE, dir_, args, sig, ready, "stderr.txt");
    err_ = readFile(dir_ / "stderr.txt");
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  }

  fs::path dir_;
  std::string err_;
};

// The CSV holds whole frames 0..K in order (every active body once per frame, every row
// complete) and the summary JSON agrees with it; returns K + 1.
int checkCsvAndSummary(const fs::path& csv, const fs::path& summary) {
  std::istringstream in(readFile(csv));
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line, "frame,time,body,x,y,z,qw,qx,qy,qz,vx,vy,vz,wx,wy,wz");
  int frame = -1, rows = 0;
  while (std::getline(in, line)) {
    EXPECT_EQ(std::count(line.begin(), line.end(), ','), 15) << line;
    const int f = std::stoi(line.substr(0, line.find(',')));
    if (f != frame) {
      EXPECT_EQ(f, frame + 1) << "frames in order, none missing";
      if (frame >= 0) {
        EXPECT_EQ(rows, 2) << "both cubes in frame " << frame;
      }
      frame = f;
      rows = 0;
    }
    ++rows;
  }
  EXPECT_EQ(rows, 2) << "the last frame is complete";
  const auto json = nlohmann::json::parse(readFile(summary));  // throws if not valid JSON
  EXPECT_EQ(json.at("frames").get<int>(), frame + 1);
  return frame + 1;
}

TEST_F(OutputRules, SimulateStopsOnSigtermOrSigintWithValidOutputs) {
  for (const int sig : {SIGTERM, SIGINT}) {
    fs::remove(dir_ / "run.csv");
    fs::remove(dir_ / "run.json");
    const int code = interrupt(
        {"simulate", "long.toml", "--csv", "run.csv", "--summary", "run.json", "--quiet"}, sig,
        [&] { return partialBytes(dir_) > 0; });  // CSV rows written: frames are flowing
    EXPECT_EQ(code, 128 + sig) << err_;
    int left = 0;
    partialBytes(dir_, &left);
    EXPECT_EQ(left, 0) << "temporary files left behind";
    ASSERT_TRUE(fs::exists(dir_ / "run.csv")) << err_;
    const int frames = checkCsvAndSummary(dir_ / "run.csv", dir_ / "run.json");
    EXPECT_GT(frames, 0);
    EXPECT_LT(frames, 18001) << "stopped, not finished";
    EXPECT_NE(err_.find("interrupted; frames 0.." + std::to_string(frames - 1)), std::string::npos)
        << err_;
    EXPECT_NE(err_.find("run.csv"), std::string::npos) << "says what was written: " << err_;
  }
}

TEST_F(OutputRules, RenderStopsOnSigtermOrSigintWithAPlayableMp4) {
  for (const int sig : {SIGTERM, SIGINT}) {
    fs::remove(dir_ / "cut.mp4");
    // The muxer keeps its data until the end, so the progress line (stderr, not a terminal:
    // a line after the first second of drawing, then every 5 s) tells when frames are drawn;
    // drawing and encoding all 901 frames takes far longer. (At 1280x720: once the cubes rest
    // nothing is redrawn, and a smaller picture encodes in a second.)
    const int code = interrupt(
        {"render", "minute.toml", "-o", "cut.mp4", "--size", "1280x720"}, sig,
        [&] { return readFile(dir_ / "stderr.txt").find("(drawing)") != std::string::npos; });
    EXPECT_EQ(code, 128 + sig) << err_;
    // ffprobe, the independent MP4 reader: the file plays and holds whole frames.
    const std::string probeFile = (dir_ / "probe.txt").string();
    const std::string probe =
        "ffprobe -v error -count_frames -select_streams v:0 -show_entries stream=nb_read_frames "
        "-of default=nw=1 '" +
        (dir_ / "cut.mp4").string() + "' > '" + probeFile + "'";
    EXPECT_EQ(std::system(probe.c_str()), 0);
    const std::string probed = readFile(probeFile);
    std::smatch m;
    ASSERT_TRUE(std::regex_search(probed, m, std::regex("nb_read_frames=(\\d+)"))) << probed;
    EXPECT_GT(std::stoi(m[1].str()), 0);
    EXPECT_LT(std::stoi(m[1].str()), 901) << "stopped, not finished";
    EXPECT_NE(err_.find("interrupted;"), std::string::npos) << err_;
    EXPECT_NE(err_.find("cut.mp4"), std::string::npos) << err_;
  }
}

TEST_F(OutputRules, AnExistingOutputNeedsYAndNKeepsIt) {
  ASSERT_EQ(run("simulate cubes.toml --csv a.csv"), 0) << err_;
  std::ofstream(dir_ / "a.csv") << "mine";
  EXPECT_EQ(run("simulate cubes.toml --csv a.csv"), 1);
  EXPECT_NE(err_.find("a.csv: already exists; use -y"), std::string::npos) << err_;
  EXPECT_EQ(run("simulate cubes.toml --csv a.csv -n"), 1);
  EXPECT_NE(err_.find("not overwritten (-n)"), std::string::npos) << err_;
  EXPECT_EQ(readFile(dir_ / "a.csv"), "mine");
  EXPECT_EQ(run("simulate cubes.toml --csv a.csv -y"), 0) << err_;
  EXPECT_NE(readFile(dir_ / "a.csv"), "mine");
  // Render and bakes follow the same rule; one existing frame of a sequence is enough.
  std::ofstream(dir_ / "f_05.png") << "mine";
  EXPECT_EQ(run("render cubes.toml --size 32x32 -o f_##.png"), 1);
  EXPECT_NE(err_.find("f_05.png: already exists"), std::string::npos) << err_;
  EXPECT_FALSE(fs::exists(dir_ / "f_00.png")) << "refused before drawing anything";
  std::ofstream(dir_ / "run.bake") << "mine";
  EXPECT_EQ(run("simulate cubes.toml --bake run.bake"), 1);
  EXPECT_EQ(readFile(dir_ / "run.bake"), "mine");
}

TEST_F(OutputRules, AnInputIsNeverOverwrittenWhateverTheFlags) {
  const std::string scene = readFile(dir_ / "cubes.toml");
  const std::string mesh = readFile(dir_ / "meshes/cube.obj");
  EXPECT_EQ(run("simulate cubes.toml --csv cubes.toml -y"), 1);
  EXPECT_NE(err_.find("is an input of this run"), std::string::npos) << err_;
  EXPECT_EQ(run("simulate cubes.toml --summary meshes/cube.obj -y"), 1);
  EXPECT_EQ(run("simulate cubes.toml --bake ./meshes/../cubes.toml -y"), 1);
  EXPECT_EQ(run("render cubes.toml --size 32x32 --frames 0:0 -o meshes/cube.obj -y"), 1);
  EXPECT_EQ(readFile(dir_ / "cubes.toml"), scene);
  EXPECT_EQ(readFile(dir_ / "meshes/cube.obj"), mesh);
  // A bake is an input of a render from it.
  ASSERT_EQ(run("simulate cubes.toml --bake run.bake"), 0) << err_;
  const std::string bake = readFile(dir_ / "run.bake");
  EXPECT_EQ(run("render run.bake --frames 0:0 -o run.bake -y"), 1);
  EXPECT_EQ(readFile(dir_ / "run.bake"), bake);
}

TEST_F(OutputRules, EveryCommandCreatesOutputFolders) {
  EXPECT_EQ(run("simulate cubes.toml --csv a/b/run.csv --summary c/run.json --bake d/e/run.bake"),
            0)
      << err_;
  EXPECT_TRUE(fs::exists(dir_ / "a/b/run.csv"));
  EXPECT_TRUE(fs::exists(dir_ / "c/run.json"));
  EXPECT_TRUE(fs::exists(dir_ / "d/e/run.bake"));
  EXPECT_EQ(run("render cubes.toml --size 32x32 --frames 0:0 -o f/g/one.png"), 0) << err_;
  EXPECT_TRUE(fs::exists(dir_ / "f/g/one.png"));
}

}  // namespace

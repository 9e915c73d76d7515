// `voxfall render` end to end: runs the built binary and checks what users and scripts rely
// on, with ffprobe as the oracle for the video: the default output path, frame count and rate,
// the same checksum as `voxfall simulate`, a frame rendered alone equal to the same frame of a
// full run, Ctrl-C leaving a playable MP4 and exit code 130, and bad options failing cleanly.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <thread>

#include "render_test_util.h"

namespace {

namespace fs = std::filesystem;

// VOXFALL_TEST_EXE in the environment overrides the binary (to try another build).
std::string exe() {
  const char* override = std::getenv("VOXFALL_TEST_EXE");
  return override ? override : VOXFALL_EXE;
}
const std::string kCubes = std::string(VOXFALL_SOURCE_DIR) + "/scenes/cubes.toml";
const std::string kCrosses = std::string(VOXFALL_SOURCE_DIR) + "/scenes/crosses.toml";

std::string readFile(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

class RenderCommand : public ::testing::Test {
 protected:
  RenderCommand() : dir_("render_cmd") {}
  void SetUp() override {
    int code = -1;
    std::string command = "'";  // built by appending: GCC 12 warns falsely on "lit" + string&&
    command.append(exe()).append("' render --help >/dev/null 2>&1");
    vf::test::runCommand(command, &code);
    ASSERT_EQ(code, 0) << "`voxfall render` is not available: register it in render/cli/main.cpp "
                          "(vf::cli::addRenderCommand)";
  }
  // Runs `voxfall ARGS` in the scratch folder (so out/ lands there); returns the exit code.
  int run(const std::string& args) {
    const std::string cmd = "cd '" + dir_.path().string() + "' && env -u DISPLAY '" + exe() + "' " +
                            args + " >stdout.txt 2>stderr.txt </dev/null";
    const int status = std::system(cmd.c_str());
    out_ = readFile(dir_.path() / "stdout.txt");
    err_ = readFile(dir_.path() / "stderr.txt");
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  }
  std::string checksum() const {
    std::smatch m;
    return std::regex_search(out_, m, std::regex("checksum ([0-9a-f]{16})")) ? m[1].str() : "";
  }
  std::string probe(const std::string& file, const std::string& entries) {
    return vf::test::runCommand(
        "ffprobe -v error -count_frames -select_streams v:0 "
        "-show_entries " +
        entries + " -of default=nw=1 '" + (dir_.path() / file).string() + "'");
  }

  vf::test::ScratchDir dir_;
  std::string out_, err_;
};

TEST_F(RenderCommand, DefaultOutputIsAnMp4NamedAfterTheSceneWithTheSimulateChecksum) {
  ASSERT_EQ(run("simulate '" + kCubes + "'"), 0) << err_;
  const std::string simulated = checksum();
  ASSERT_FALSE(simulated.empty()) << out_;
  // cubes.toml: 2 s at 30 fps -> frames 0..60.
  ASSERT_EQ(run("render '" + kCubes + "' --size 96x64 --quiet"), 0) << err_;
  EXPECT_TRUE(fs::exists(dir_.path() / "out/cubes.mp4"));
  EXPECT_EQ(checksum(), simulated) << "render and simulate disagree on the trajectory";
  EXPECT_NE(out_.find("out/cubes.mp4"), std::string::npos) << out_;
  EXPECT_EQ(probe("out/cubes.mp4", "stream=codec_name,width,height,r_frame_rate,nb_read_frames"),
            "codec_name=h264\nwidth=96\nheight=64\nr_frame_rate=30/1\nnb_read_frames=61\n");
}

TEST_F(RenderCommand, FpsOptionSetsTheFrameTimes) {
  ASSERT_EQ(run("render '" + kCubes + "' -o clip.mp4 --size 64x48 --fps 10 --frames 5:8 -q"), 0)
      << err_;
  // Frames 5..8 at 10 fps: shown at t = 0.5 .. 0.8 s (time base 1/10, pts = frame number).
  const std::string probed = probe("clip.mp4", "stream=time_base,nb_read_frames:frame=pts");
  EXPECT_NE(probed.find("time_base=1/10\n"), std::string::npos) << probed;
  EXPECT_NE(probed.find("nb_read_frames=4\n"), std::string::npos) << probed;
  EXPECT_NE(probed.find("pts=5\npts=6\npts=7\npts=8\n"), std::string::npos) << probed;
}

TEST_F(RenderCommand, AFrameRenderedAloneEqualsTheSameFrameOfTheSequence) {
  ASSERT_EQ(run("render '" + kCubes + "' -o 'seq/f_####.png' --size 96x64 -q"), 0) << err_;
  ASSERT_TRUE(fs::exists(dir_.path() / "seq/f_0000.png"));
  ASSERT_TRUE(fs::exists(dir_.path() / "seq/f_0060.png"));
  EXPECT_FALSE(fs::exists(dir_.path() / "seq/f_0061.png"));
  ASSERT_EQ(run("render '" + kCubes + "' -o alone.png --frames 30:30 --size 96x64 -q"), 0) << err_;
  const std::string alone = readFile(dir_.path() / "alone.png");
  ASSERT_FALSE(alone.empty());
  EXPECT_TRUE(alone == readFile(dir_.path() / "seq/f_0030.png"))
      << "frame 30 differs between --frames 30:30 and a full run";
}

TEST_F(RenderCommand, InterruptLeavesAPlayableMp4AndExitCode130) {
  // Long enough (the crosses' 1,081 frames at 640x360 and 60 fps, about ten seconds or more:
  // frames that change little are drawn in part, so short clips finish within a second) that
  // SIGINT lands mid-render.
  const std::string video = (dir_.path() / "cut.mp4").string();
  const pid_t child = ::fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    ::unsetenv("DISPLAY");
    const int devnull = ::open("/dev/null", O_WRONLY);
    ::dup2(devnull, 1);
    ::dup2(devnull, 2);
    const std::string exePath = exe();
    ::execl(exePath.c_str(), exePath.c_str(), "render", kCrosses.c_str(), "-o", video.c_str(),
            "--size", "640x360", "--fps", "60", "--quiet", static_cast<char*>(nullptr));
    ::_exit(127);
  }
  // Wait for the encoder's temporary file (GL set up, scene simulated), then a few frames more.
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(30);
  while (vf::test::partialFiles(dir_.path()) == 0 && std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(1500));
  ::kill(child, SIGINT);
  int status = 0;
  ::waitpid(child, &status, 0);
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 130);
  EXPECT_EQ(vf::test::partialFiles(dir_.path()), 0);
  const std::string probed = probe("cut.mp4", "stream=codec_name,nb_read_frames");
  std::smatch m;
  ASSERT_TRUE(std::regex_search(probed, m, std::regex("nb_read_frames=(\\d+)"))) << probed;
  const int frames = std::stoi(m[1].str());
  EXPECT_GT(frames, 0);
  EXPECT_LT(frames, 1081);  // interrupted, not finished
}

TEST_F(RenderCommand, ANamedChaseCameraWithTrailsDrawsFrameKAloneAsInTheFullRun) {
  // The chase camera's lag and the trails depend on frames 0..k: frame 30 drawn alone must
  // still equal frame 30 of the whole clip, and differ from the default camera's frame 30.
  std::string scene = readFile(kCubes);
  const std::string mesh = std::string(VOXFALL_SOURCE_DIR) + "/scenes/meshes/cube.obj";
  scene = std::regex_replace(scene, std::regex("\"meshes/cube.obj\""), "\"" + mesh + "\"");
  scene +=
      "\n[cameras.chase]\nfollow = 1\nsmoothing = 0.3\ntrail = 0.5\n"
      "position = [1.5, -3.0, 1.2]\nlook_at = [0.0, 0.0, 0.2]\n";
  std::ofstream(dir_.path() / "chase.toml") << scene;
  ASSERT_EQ(run("render chase.toml --camera chase -o 'seq/f_####.png' --size 96x64 -q"), 0) << err_;
  ASSERT_EQ(run("render chase.toml --camera chase -o alone.png --frames 30:30 --size 96x64 -q"), 0)
      << err_;
  const std::string alone = readFile(dir_.path() / "alone.png");
  ASSERT_FALSE(alone.empty());
  EXPECT_TRUE(alone == readFile(dir_.path() / "seq/f_0030.png"))
      << "frame 30 differs between --frames 30:30 and a full run";
  ASSERT_EQ(run("render chase.toml -o default.png --frames 30:30 --size 96x64 -q"), 0) << err_;
  EXPECT_FALSE(alone == readFile(dir_.path() / "default.png"));
  // An unknown name is an input error naming the choices.
  EXPECT_EQ(run("render chase.toml --camera drone -o x.png --frames 0:0 -q"), 1);
  EXPECT_NE(err_.find("no camera named 'drone'; the scene has: camera, chase"), std::string::npos)
      << err_;
  EXPECT_FALSE(fs::exists(dir_.path() / "x.png"));
}

TEST_F(RenderCommand, ASizeFromTheSceneOrFromSizeMeetsOneRuleWithOneMessage) {
  // The same odd size from [output] and from --size: one even-size check (the MP4 encoder's),
  // so one message; a PNG of the odd size is fine either way.
  fs::create_directories(dir_.path() / "meshes");
  fs::copy_file(fs::path(VOXFALL_SOURCE_DIR) / "scenes/meshes/cube.obj",
                dir_.path() / "meshes/cube.obj");
  const std::string cubes = readFile(kCubes);
  std::ofstream(dir_.path() / "odd.toml") << cubes << "\n[output]\nwidth = 101\nheight = 64\n";
  std::ofstream(dir_.path() / "zero.toml") << cubes << "\n[output]\nwidth = 0\n";
  const std::string odd =
      "voxfall: error: x.mp4: MP4 frame size 101x64 must be even in both directions";
  EXPECT_EQ(run("render odd.toml -o x.mp4 -q"), 1);
  const std::string fromScene = err_;
  EXPECT_EQ(fromScene.rfind(odd, 0), 0u) << fromScene;
  EXPECT_EQ(run("render '" + kCubes + "' --size 101x64 -o x.mp4 -q"), 1);
  EXPECT_EQ(err_, fromScene);
  EXPECT_FALSE(fs::exists(dir_.path() / "x.mp4"));
  EXPECT_EQ(run("render odd.toml --frames 3:3 -o odd.png -q"), 0) << err_;
  EXPECT_EQ(run("render '" + kCubes + "' --frames 3:3 --size 101x64 -o odd_size.png -q"), 0)
      << err_;
  EXPECT_TRUE(readFile(dir_.path() / "odd.png") == readFile(dir_.path() / "odd_size.png"));
  // The same size limit in the same words: at the key of [output], or as a usage error.
  const std::string zero = "the frame width must be 1..16384 pixels, got 0";
  EXPECT_EQ(run("render zero.toml -o x.mp4 -q"), 1);
  EXPECT_NE(
      err_.find("zero.toml:" + std::to_string(std::count(cubes.begin(), cubes.end(), '\n') + 3) +
                ":9: " + zero),
      std::string::npos)
      << err_;
  EXPECT_EQ(run("render '" + kCubes + "' --size 0x64 -o x.mp4 -q"), 2);
  EXPECT_NE(err_.find("--size: " + zero), std::string::npos) << err_;
}

TEST_F(RenderCommand, BadOptionsFailBeforeAnyOutput) {
  // Odd size for an MP4, frames outside the scene, an unknown output kind.
  EXPECT_EQ(run("render '" + kCubes + "' -o odd.mp4 --size 101x64 -q"), 1);
  EXPECT_NE(err_.find("even"), std::string::npos) << err_;
  EXPECT_EQ(run("render '" + kCubes + "' -o late.mp4 --frames 70:80 -q"), 1);
  EXPECT_NE(err_.find("0:60"), std::string::npos) << err_;
  EXPECT_EQ(run("render '" + kCubes + "' -o clip.avi -q"), 1);
  EXPECT_NE(err_.find("clip.avi"), std::string::npos) << err_;
  // Usage errors (CLI11 validators) exit with 2.
  EXPECT_EQ(run("render '" + kCubes + "' --size big -q"), 2);
  EXPECT_EQ(run("render '" + kCubes + "' --gl vulkan -q"), 2);
  // An MP4 has no alpha channel: a transparent background is refused, naming the option or
  // the scene, before anything is simulated; an overlay list must name overlays.
  EXPECT_EQ(run("render '" + kCubes + "' -o clear.mp4 --alpha -q"), 1);
  EXPECT_EQ(err_.rfind("voxfall: error: --alpha: an MP4 (H.264) has no alpha channel", 0), 0u)
      << err_;
  std::string cubes = readFile(kCubes);
  cubes.replace(cubes.find("meshes/"), 7, std::string(VOXFALL_SOURCE_DIR) + "/scenes/meshes/");
  std::ofstream(dir_.path() / "clear.toml") << cubes << "\n[output]\nalpha = true\n";
  EXPECT_EQ(run("render clear.toml -o clear.mp4 -q"), 1);
  EXPECT_EQ(err_.rfind("voxfall: error: clear.toml: an MP4 (H.264) has no alpha channel", 0), 0u)
      << err_;
  EXPECT_EQ(run("render '" + kCubes + "' --overlay time,clock -q"), 2);
  EXPECT_NE(err_.find("--overlay"), std::string::npos) << err_;
  for (const char* name : {"odd.mp4", "late.mp4", "clip.avi", "clear.mp4", "out"}) {
    EXPECT_FALSE(fs::exists(dir_.path() / name)) << name;
  }
  EXPECT_EQ(vf::test::partialFiles(dir_.path()), 0);
}

}  // namespace

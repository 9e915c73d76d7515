// Time remapping end to end (`voxfall render --speed X`, [output] speed): frame k shows the
// state at t = k X / fps with the exactness of the scene's own frames, so a frame drawn at one
// speed is, byte for byte, the frame at the same time drawn at another (PNG files compared
// whole: the same pixels give the same bytes). The scene slides a cube across the floor and
// keeps it moving to the end, and its last frame (31 at 30 fps) is one that speed 2 does not
// draw: a framing fitted to the drawn frames alone would frame speed 2 differently.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <regex>
#include <string>

#include "render_test_util.h"
#include "tests/support/voxfall_command.h"

namespace {

namespace fs = std::filesystem;
using vf::test::readFile;

const std::string kScenes = std::string(VOXFALL_SOURCE_DIR) + "/scenes";

// A cube sliding at 4 m/s on a floor of friction 0.1 (it slows by about 1 m/s^2: still moving
// at the end) beside one at rest; 31/30 s at 30 fps: frames 0..31.
std::string slidingScene(const std::string& output = "") {
  return "[simulation]\nduration = 1.0333333333333334\nlevel = 2\nfps = 30\n"
         "[contact]\nfriction = { body_body = 0.3, body_ground = 0.1 }\n"
         "[ground]\nplane = 0.0\n"
         "[shapes.cube]\nmesh = \"" +
         kScenes +
         "/meshes/cube.obj\"\nscale = 0.2\ndensity = 800\n"
         "[[bodies]]\nshape = \"cube\"\nposition = [0.0, 0.0, 0.1]\nvelocity = [4.0, 0.0, 0.0]\n"
         "[[bodies]]\nshape = \"cube\"\nposition = [0.0, 1.0, 0.1]\n" +
         output;
}

class TimeRemap : public ::testing::Test {
 protected:
  TimeRemap() : dir_("time_remap") { std::ofstream(dir_.file("slide.toml")) << slidingScene(); }
  // Renders the scene at `speed` into folder `name` as PNG frames; returns the exit code.
  int render(const std::string& name, const std::string& extra) {
    const vf::test::CommandResult r = vf::test::runVoxfall(
        VOXFALL_EXE, dir_.path(),
        "render slide.toml --size 64x36 -q -o " + name + "/f_###.png " + extra);
    out_ = r.out;
    err_ = r.err;
    return r.code;
  }
  std::string frame(const std::string& name, int k) const {
    char file[32];
    std::snprintf(file, sizeof file, "/f_%03d.png", k);
    return readFile(dir_.path() / (name + file));
  }
  int frames(const std::string& name) const {
    int n = 0;
    for (const auto& e : fs::directory_iterator(dir_.path() / name))
      n += e.path().extension() == ".png" ? 1 : 0;
    return n;
  }
  std::string checksum() const {
    std::smatch m;
    return std::regex_search(out_, m, std::regex("checksum ([0-9a-f]{16})")) ? m[1].str() : "";
  }

  vf::test::ScratchDir dir_;
  std::string out_, err_;
};

TEST_F(TimeRemap, FrameKAtSpeedTwoIsFrame2KAtSpeedOneByteForByte) {
  ASSERT_EQ(render("x1", ""), 0) << err_;
  const std::string atSpeed1 = checksum();
  ASSERT_EQ(render("x2", "--speed 2"), 0) << err_;
  // The simulation is the scene's whatever the speed: drawing never steers it.
  EXPECT_EQ(checksum(), atSpeed1);
  // floor(31 / 2) + 1 frames: the video lasts half as long.
  ASSERT_EQ(frames("x1"), 32);
  ASSERT_EQ(frames("x2"), 16);
  for (int k = 0; k < 16; ++k) {
    const std::string a = frame("x2", k);
    ASSERT_FALSE(a.empty()) << k;
    EXPECT_TRUE(a == frame("x1", 2 * k)) << "frame " << k << " at speed 2 is not frame " << 2 * k;
  }
  // The control: the cube moves, so neighbouring frames differ and the comparison can fail.
  EXPECT_FALSE(frame("x2", 5) == frame("x1", 11));
}

TEST_F(TimeRemap, FrameTwoKAtHalfSpeedIsFrameKAtSpeedOne) {
  ASSERT_EQ(render("x1", ""), 0) << err_;
  // The scene key does what the option does.
  std::ofstream(dir_.file("slide.toml")) << slidingScene("[output]\nspeed = 0.5\n");
  ASSERT_EQ(render("half", ""), 0) << err_;
  ASSERT_EQ(frames("half"), 63);  // 31 / 0.5 + 1: twice as long
  for (int k = 0; k < 32; ++k)
    EXPECT_TRUE(frame("half", 2 * k) == frame("x1", k)) << "frame " << 2 * k << " at speed 0.5";
  // In between: new states, drawn (the cube is half way between frames 3 and 4).
  EXPECT_FALSE(frame("half", 7) == frame("x1", 3));
  EXPECT_FALSE(frame("half", 7) == frame("x1", 4));
}

TEST_F(TimeRemap, ASpeedThatIsNoNumberOrMakesTooManyFramesIsRefused) {
  EXPECT_EQ(render("bad", "--speed 0"), 2);  // a usage error: from 0.001
  EXPECT_NE(err_.find("--speed"), std::string::npos) << err_;
  std::ofstream(dir_.file("slide.toml")) << slidingScene("[output]\nspeed = -1.0\n");
  EXPECT_EQ(render("bad", ""), 1);
  EXPECT_NE(err_.find("slide.toml:21:9: 'speed' must be > 0"), std::string::npos) << err_;
  std::ofstream(dir_.file("slide.toml")) << slidingScene("[output]\nspeed = 1e-9\n");
  EXPECT_EQ(render("bad", ""), 1);
  EXPECT_NE(err_.find("duration * fps / speed"), std::string::npos) << err_;
  EXPECT_FALSE(fs::exists(dir_.path() / "bad"));
}

}  // namespace

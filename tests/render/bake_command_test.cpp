// Simulate once, render many, end to end with the built binary:
// `voxfall simulate SCENE --bake FILE` then `voxfall render FILE` gives the same PNG bytes as
// `voxfall render SCENE`, needs no scene file and takes no step, and frame ranges rendered by
// separate processes join into the frames of one run.
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

class BakeCommand : public ::testing::Test {
 protected:
  BakeCommand() : dir_("bake_cmd") {
    // The scene and its mesh in the scratch folder, so a test can take the scene away.
    fs::create_directories(dir_.path() / "meshes");
    const fs::path scenes = fs::path(VOXFALL_SOURCE_DIR) / "scenes";
    fs::copy_file(scenes / "cubes.toml", dir_.path() / "cubes.toml");
    fs::copy_file(scenes / "meshes/cube.obj", dir_.path() / "meshes/cube.obj");
  }
  // Runs `voxfall ARGS --quiet` in the scratch folder; returns the exit code.
  int run(const std::string& args) {
    const vf::test::CommandResult r =
        vf::test::runVoxfall(VOXFALL_EXE, dir_.path(), args + " --quiet");
    out_ = r.out;
    err_ = r.err;
    return r.code;
  }
  std::string checksum() const {
    std::smatch m;
    return std::regex_search(out_, m, std::regex("checksum ([0-9a-f]{16})")) ? m[1].str() : "";
  }
  // Every file of folder `a` has the same bytes in folder `b`, and the counts agree.
  void expectSameFrames(const std::string& a, const std::string& b, int count) {
    int n = 0;
    for (const auto& e : fs::directory_iterator(dir_.path() / a)) {
      const fs::path other = dir_.path() / b / e.path().filename();
      ASSERT_TRUE(fs::exists(other)) << other;
      EXPECT_TRUE(readFile(e.path()) == readFile(other)) << e.path().filename() << " differs";
      ++n;
    }
    EXPECT_EQ(n, count);
    EXPECT_EQ(std::distance(fs::directory_iterator(dir_.path() / b), fs::directory_iterator{}),
              count);
  }

  vf::test::ScratchDir dir_;
  std::string out_, err_;
};

TEST_F(BakeCommand, ABakeRendersTheScenesPixelsWithoutTheSceneOrAStep) {
  ASSERT_EQ(run("simulate cubes.toml --bake run.bake"), 0) << err_;
  const std::string simulated = checksum();
  // cubes.toml: 2 s at 30 fps, frames 0..60.
  ASSERT_EQ(run("render cubes.toml --size 96x64 -o scene/f_##.png"), 0) << err_;
  EXPECT_EQ(checksum(), simulated);
  fs::remove(dir_.path() / "cubes.toml");  // the bake alone must do
  ASSERT_EQ(run("render run.bake --size 96x64 -o bake/f_##.png"), 0) << err_;
  EXPECT_EQ(checksum(), simulated) << "the bake carries its run's checksum";
  EXPECT_NE(out_.find("steps simulated: 0"), std::string::npos) << out_;
  expectSameFrames("scene", "bake", 61);
}

TEST_F(BakeCommand, OneFrameAndSeparateRangesOfABakeEqualOneRun) {
  ASSERT_EQ(run("simulate cubes.toml --bake run.bake"), 0) << err_;
  ASSERT_EQ(run("render run.bake --size 96x64 -o whole/f_##.png"), 0) << err_;
  // Three processes, as a job scheduler would run them, into one folder.
  ASSERT_EQ(run("render run.bake --size 96x64 --frames 0:29 -o parts/f_##.png"), 0) << err_;
  ASSERT_EQ(run("render run.bake --size 96x64 --frames 30:59 -o parts/f_##.png"), 0) << err_;
  ASSERT_EQ(run("render run.bake --size 96x64 --frames 60:60 -o parts/f_##.png"), 0) << err_;
  EXPECT_NE(out_.find("steps simulated: 0"), std::string::npos) << out_;
  expectSameFrames("whole", "parts", 61);
}

TEST_F(BakeCommand, ABakeRendersAtAnotherFrameRateAsTheSceneDoes) {
  // The bake holds every step, so frames at 60 fps come out as the scene's at 60 fps.
  ASSERT_EQ(run("simulate cubes.toml --bake run.bake"), 0) << err_;
  ASSERT_EQ(run("render cubes.toml --fps 60 --size 96x64 --frames 37:41 -o scene/f_###.png"), 0)
      << err_;
  ASSERT_EQ(run("render run.bake --fps 60 --size 96x64 --frames 37:41 -o bake/f_###.png"), 0)
      << err_;
  expectSameFrames("scene", "bake", 5);
}

TEST_F(BakeCommand, ABakeKeepsTheScenesNamedCameras) {
  // Two named cameras unlike [camera] (cubes.toml has none: the automatic one): a chase camera
  // with lag and a trail, and a keyframed path. Each draws other pixels than the default, so
  // a bake that lost them, or rendered its default camera instead, fails the comparison.
  std::ofstream(dir_.path() / "cubes.toml", std::ios::app)
      << "\n[cameras.chase]\nfollow = [0, 1]\nsmoothing = 0.3\nposition = [1.5, -2.5, 1.0]\n"
         "look_at = [0.2, 0.1, 0.15]\ntrail = 1.0\n"
         "\n[cameras.path]\npath = [\n"
         "  { time = 0.0, position = [3.0, -3.0, 2.0], look_at = [0.5, 0.0, 0.2], fov = 35 },\n"
         "  { time = 2.0, position = [-2.0, -3.0, 1.5], look_at = [0.0, 0.1, 0.2], fov = 50 },\n"
         "]\n";
  ASSERT_EQ(run("simulate cubes.toml --bake run.bake"), 0) << err_;
  for (const std::string camera : {"chase", "path"}) {
    ASSERT_EQ(run("render cubes.toml --camera " + camera +
                  " --size 96x64 --frames 20:24 -o scene_" + camera + "/f_##.png"),
              0)
        << err_;
    ASSERT_EQ(run("render run.bake --camera " + camera + " --size 96x64 --frames 20:24 -o bake_" +
                  camera + "/f_##.png"),
              0)
        << err_;
    expectSameFrames("scene_" + camera, "bake_" + camera, 5);
  }
  ASSERT_EQ(run("render cubes.toml --size 96x64 --frames 20:24 -o default/f_##.png"), 0) << err_;
  EXPECT_FALSE(readFile(dir_.path() / "default/f_22.png") ==
               readFile(dir_.path() / "bake_chase/f_22.png"))
      << "the chase camera must show another picture than the default one";

  EXPECT_EQ(run("render run.bake --camera drone -o x.mp4"), 1);
  EXPECT_NE(err_.find("run.bake: no camera named 'drone'; the scene has: camera, chase, path"),
            std::string::npos)
      << err_;
  EXPECT_FALSE(fs::exists(dir_.path() / "x.mp4"));
}

TEST_F(BakeCommand, ABakeKeepsTheScenesLightAndSmoothShapes) {
  // A low sun from the west in orange and smooth shading on the cubes (a crease above their 90
  // degree edges): both change the pixels, so a bake that lost either draws other bytes.
  std::ofstream(dir_.path() / "cubes.toml", std::ios::app)
      << "\n[light]\nazimuth = 270\nelevation = 20\ncolor = [1.0, 0.6, 0.3]\n";
  std::string scene = readFile(dir_.path() / "cubes.toml");
  const std::string shape = "[shapes.cube]\n";
  ASSERT_NE(scene.find(shape), std::string::npos);
  std::ofstream(dir_.path() / "smooth.toml")
      << scene.insert(scene.find(shape) + shape.size(), "smooth = 100\n");
  ASSERT_EQ(run("simulate smooth.toml --bake run.bake"), 0) << err_;
  ASSERT_EQ(run("render smooth.toml --size 96x64 --frames 30 -o scene.png"), 0) << err_;
  ASSERT_EQ(run("render run.bake --size 96x64 --frames 30 -o bake.png"), 0) << err_;
  EXPECT_TRUE(readFile(dir_.path() / "scene.png") == readFile(dir_.path() / "bake.png"));
  ASSERT_EQ(run("render cubes.toml --size 96x64 --frames 30 -o flat.png"), 0) << err_;
  EXPECT_FALSE(readFile(dir_.path() / "flat.png") == readFile(dir_.path() / "bake.png"))
      << "smooth shading shows";
}

TEST_F(BakeCommand, AVersion1BakeStillRendersWithItsOneCamera) {
  // Version 1 headers had `camera` only, versions 1 and 2 no shape `repair`, `rock` or `up`, and
  // versions 1 to 3 no light, terrain texture, shape `smooth` or camera `offset_given`: rewrite
  // this run's header as version 1 would have been written (no `cameras`, no camera `name` or
  // `where`, none of those keys) and check it draws the same frames.
  ASSERT_EQ(run("simulate cubes.toml --bake run.bake"), 0) << err_;
  std::string bytes = readFile(dir_.path() / "run.bake");
  const std::size_t start = bytes.find('\n') + 1, end = bytes.find('\n', start);
  std::string header = bytes.substr(start, end - start);
  auto cut = [&header](const std::regex& what) { header = std::regex_replace(header, what, ""); };
  cut(std::regex(R"re(,?"light":\{[^}]*\})re"));
  cut(std::regex(R"re(,?"terrain_texture":"[^"]*")re"));
  cut(std::regex(R"re(,?"smooth":null)re"));
  cut(std::regex(R"re(,?"offset_given":(true|false))re"));
  cut(std::regex(R"re(,?"cameras":\[[^\]]*\])re"));
  cut(std::regex(R"re("name":"camera",)re"));
  cut(std::regex(R"re(,"where":"[^"]*")re"));  // the header's keys are sorted: last
  cut(std::regex(R"re("repair":false,"rock":null,)re"));
  cut(std::regex(R"re(,"up":"z")re"));
  header = std::regex_replace(header, std::regex(R"re("version":4)re"), R"re("version":1)re");
  for (const char* key : {"\"cameras\"", "\"light\"", "\"terrain_texture\"", "\"smooth\"",
                          "\"offset_given\"", "\"rock\"", "\"up\":\"z\""})
    ASSERT_EQ(header.find(key), std::string::npos) << key << " in " << header;
  ASSERT_NE(header.find(R"re("version":1)re"), std::string::npos) << header;
  std::ofstream(dir_.path() / "v1.bake", std::ios::binary)
      << bytes.substr(0, start) << header << bytes.substr(end);
  ASSERT_EQ(run("render run.bake --size 96x64 --frames 0:3 -o v4/f_##.png"), 0) << err_;
  ASSERT_EQ(run("render v1.bake --size 96x64 --frames 0:3 -o v1/f_##.png"), 0) << err_;
  expectSameFrames("v4", "v1", 4);
  EXPECT_EQ(run("render v1.bake --camera chase -o x.mp4"), 1);
  EXPECT_NE(err_.find("v1.bake: no camera named 'chase'; the scene has: camera"), std::string::npos)
      << err_;
  // A version from the future is refused by number, not misread.
  header = std::regex_replace(header, std::regex(R"re("version":1)re"), R"re("version":5)re");
  std::ofstream(dir_.path() / "v5.bake", std::ios::binary)
      << bytes.substr(0, start) << header << bytes.substr(end);
  EXPECT_EQ(run("render v5.bake -o x.mp4"), 1);
  EXPECT_NE(err_.find("bake version 5 is not one this voxfall reads (1..4)"), std::string::npos)
      << err_;
}

TEST_F(BakeCommand, PhysicsOptionsAndBrokenBakesAreRefused) {
  ASSERT_EQ(run("simulate cubes.toml --bake run.bake"), 0) << err_;
  EXPECT_EQ(run("render run.bake --level 3 -o x.mp4"), 1);
  EXPECT_NE(err_.find("--level, --step, --collider"), std::string::npos) << err_;
  // Cut the body short: the reader names the file and the size it expected.
  const std::string bytes = readFile(dir_.path() / "run.bake");
  std::ofstream(dir_.path() / "short.bake", std::ios::binary) << bytes.substr(0, bytes.size() - 8);
  EXPECT_EQ(run("render short.bake -o y.mp4"), 1);
  EXPECT_NE(err_.find("short.bake: the bake body holds"), std::string::npos) << err_;
  EXPECT_FALSE(fs::exists(dir_.path() / "x.mp4"));
  EXPECT_FALSE(fs::exists(dir_.path() / "y.mp4"));
}

// A damaged or hand-edited bake gets one message naming the header key or the record, from
// `render` and `export` alike, and writes nothing. Unchecked, a negative fps or duration gives
// "cannot create std::vector larger than max_size()" (no file named), and a NaN state, a
// field of view of 500 degrees or a zero up vector draws nonsense (or exports NaN into glTF)
// with exit 0.
TEST_F(BakeCommand, DamagedHeadersAndRecordsAreRefusedByName) {
  ASSERT_EQ(run("simulate cubes.toml --bake run.bake"), 0) << err_;
  const std::string bytes = readFile(dir_.path() / "run.bake");
  const std::size_t start = bytes.find('\n') + 1, end = bytes.find('\n', start);
  const std::string header = bytes.substr(start, end - start);
  auto edited = [&](const std::string& from, const std::string& to) {
    const std::size_t at = header.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    return bytes.substr(0, start) + std::string(header).replace(at, from.size(), to) +
           bytes.substr(end);
  };
  const std::pair<std::string, std::string> cases[] = {
      {edited(R"("fps":30.0)", R"("fps":-1.0)"),
       ":2: bad bake header: 'scene.fps' must be a finite number > 0, got -1"},
      {edited(R"("duration":2.0)", R"("duration":-2.0)"), "'scene.duration' must be a finite"},
      {edited(R"("fov":40.0)", R"("fov":500.0)"), "'scene.camera.fov' must be in degrees"},
      {edited(R"("up":[0.0,0.0,1.0])", R"("up":[0.0,0.0,0.0])"),
       "'scene.camera.up' must be a non-zero vector"},
      {edited(R"("level":4)", R"("level":99)"), "'shapes[0].level' must be 1..10, got 99"},
      {edited(R"("width":1280)", R"("width":0)"), "scene.output: the frame width must be"},
      // From bake_fuzz: a float where an integer belongs must not be cast (undefined past int's
      // range), nor a colour past float's range.
      {edited(R"("level":4)", R"("level":5e88)"),
       "'shapes[].level' must be an integer from -2147483648 to 2147483647, got 5e+88"},
      {edited(R"("records":239)", R"("records":-1)"), "'records' must be an integer from 0 to"},
      {edited(R"("color":[0.578000009059906)", R"("color":[1e300)"),
       "colours must hold numbers in 0..1"},
      {edited(R"("inv_mass":0.0462)", R"("inv_mass":-0.0462)"),
       "'bodies[0].inv_mass' must be a finite number >= 0"},
      // Records: body 0's x in record 5 made NaN, its quaternion's w made 0.
      {bytes.substr(0, end + 1 + (5 * 29 + 2) * 8) + std::string("\0\0\0\0\0\0\xf8\x7f", 8) +
           bytes.substr(end + 1 + (5 * 29 + 3) * 8),
       "record 5: body 0's state holds a value that is not finite"},
      {bytes.substr(0, end + 1 + (5 * 29 + 5) * 8) + std::string(8, '\0') +
           bytes.substr(end + 1 + (5 * 29 + 6) * 8),
       "record 5: body 0's orientation is not a unit quaternion"},
  };
  for (const auto& [file, message] : cases) {
    std::ofstream(dir_.path() / "damaged.bake", std::ios::binary) << file;
    for (const std::string command :
         {"render damaged.bake --size 32x32 -o out.mp4", "export damaged.bake -o out.glb"}) {
      EXPECT_EQ(run(command), 1) << command;
      EXPECT_EQ(err_.rfind("voxfall: error: damaged.bake", 0), 0u) << err_;
      EXPECT_NE(err_.find(message), std::string::npos) << err_;
    }
    EXPECT_FALSE(fs::exists(dir_.path() / "out.mp4"));
    EXPECT_FALSE(fs::exists(dir_.path() / "out.glb"));
  }
  // The undamaged bake reads.
  EXPECT_EQ(run("export run.bake -o out.glb"), 0) << err_;
}

TEST_F(BakeCommand, GeneratedRocksRenderTheSamePixelsFromTheSceneAndItsBake) {
  // No mesh file: the bake regenerates the rocks (an EOTA block and a family's variant) from
  // their definitions. A rock rebuilt differently would move or reshape pixels.
  std::ofstream(dir_.path() / "rocks.toml")
      << "[simulation]\nduration = 0.5\nlevel = 3\n[ground]\nplane = 0.0\n"
         "[shapes.block]\nrock = { class = \"eota_221\", size = 1.0 }\ndensity = 2700\n"
         "[shapes.stones]\nrock = { class = \"bladed\", seed = 9, seeds = 2, volume = 0.2 }\n"
         "density = 2700\n"
         "[[bodies]]\nshape = \"block\"\nposition = [0.0, 0.0, 0.6]\n"
         "angular_velocity = [2.0, 1.0, 0.0]\n"
         "[[bodies]]\nshape = \"stones#1\"\nposition = [1.2, 0.0, 0.6]\n";
  ASSERT_EQ(run("simulate rocks.toml --bake rocks.bake"), 0) << err_;
  const std::string simulated = checksum();
  ASSERT_EQ(run("render rocks.toml --size 96x64 --frames 0:15 -o scene/f_##.png"), 0) << err_;
  EXPECT_EQ(checksum(), simulated);
  fs::remove(dir_.path() / "rocks.toml");
  ASSERT_EQ(run("render rocks.bake --size 96x64 --frames 0:15 -o bake/f_##.png"), 0) << err_;
  expectSameFrames("scene", "bake", 16);
}

}  // namespace

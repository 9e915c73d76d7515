// The voxfall command end to end: runs the built binary (VOXFALL_EXE) with std::system and
// checks what a user or a script relies on: exit codes, one error line naming file:line,
// no output file left behind by a failed run, and the shape of the CSV and JSON outputs.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;

const std::string kExe = VOXFALL_EXE;
const std::string kScenes = std::string(VOXFALL_SOURCE_DIR) + "/scenes";

std::string readFile(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

std::vector<std::string> lines(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) out.push_back(line);
  return out;
}

std::string quote(const std::string& s) { return "'" + s + "'"; }

class CliTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() /
           ("voxfall_cli_test_" + std::to_string(::getpid()) + "_" + info->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_ / "out");
  }
  void TearDown() override { fs::remove_all(dir_); }

  // Runs `voxfall ARGS`; stdout and stderr are kept in out_ and err_. Returns the exit code.
  int run(const std::string& args) {
    const fs::path outFile = dir_ / "stdout.txt", errFile = dir_ / "stderr.txt";
    const std::string cmd = quote(kExe) + " " + args + " >" + quote(outFile.string()) + " 2>" +
                            quote(errFile.string()) + " </dev/null";
    const int status = std::system(cmd.c_str());
    out_ = readFile(outFile);
    err_ = readFile(errFile);
    fs::remove(outFile);
    fs::remove(errFile);
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  }

  std::string write(const std::string& name, const std::string& text) {
    std::ofstream(dir_ / name) << text;
    return (dir_ / name).string();
  }

  std::vector<std::string> errorLines() const {
    std::vector<std::string> found;
    for (const auto& l : lines(err_)) {
      if (l.find("voxfall: error:") != std::string::npos) found.push_back(l);
    }
    return found;
  }

  fs::path dir_;
  std::string out_, err_;
};

TEST_F(CliTest, Version) {
  EXPECT_EQ(run("--version"), 0);
  EXPECT_EQ(out_.rfind("voxfall ", 0), 0u) << out_;
}

TEST_F(CliTest, UsageErrorsExitWith2) {
  EXPECT_EQ(run("simulate"), 2);  // missing SCENE
  EXPECT_EQ(errorLines().size(), 1u) << err_;
  EXPECT_EQ(run("simulate " + quote(kScenes + "/cubes.toml") + " --no-such-option"), 2);
  EXPECT_EQ(run("simulate " + quote(kScenes + "/cubes.toml") + " --level 11"), 2);
  EXPECT_EQ(run("simulate " + quote(kScenes + "/cubes.toml") + " --step fast"), 2);
  EXPECT_EQ(run(""), 2);  // a subcommand is required
}

// The run limits take what the scene's keys take: counts from 1 to 2^63 - 1 and finite
// speeds > 0. Each case is one a looser parse gets wrong: 1e20 steps clamped and the run going
// ahead, "nan" m/s passing the option and failing later as a body "over the limit of nan m/s",
// and "inf" getting a 309-digit range.
TEST_F(CliTest, RunLimitsOutsideWhatTheSceneTakesAreUsageErrors) {
  const std::string cubes = "simulate " + quote(kScenes + "/cubes.toml") + " --quiet ";
  const std::pair<std::string, std::string> cases[] = {
      {"--max-steps 100000000000000000000",
       "--max-steps: must be an integer from 1 to 9223372036854775807, got 100000000000000000000"},
      {"--max-steps 0", "--max-steps: must be an integer from 1 to"},
      {"--max-steps 1.5", "--max-steps: must be an integer from 1 to"},
      {"--max-speed nan", "--max-speed: must be a finite number > 0 (m/s), got nan"},
      {"--max-speed inf", "--max-speed: must be a finite number > 0 (m/s), got inf"},
      {"--max-speed 1e400", "--max-speed: must be a finite number > 0 (m/s), got 1e400"},
      {"--max-speed -5", "--max-speed: must be a finite number > 0"},
  };
  for (const auto& [option, message] : cases) {
    EXPECT_EQ(run(cubes + option), 2) << option;
    ASSERT_FALSE(errorLines().empty()) << option;
    EXPECT_NE(errorLines()[0].find("voxfall: error: " + message), std::string::npos) << err_;
  }
  EXPECT_EQ(run(cubes + "--max-steps 9223372036854775807 --max-speed 1e3"), 0) << err_;
}

// CLI11's range check lets "nan" through (every comparison with it is false): on that check
// alone `render --fps nan` fails on an empty frame range, `export --fps nan` with "cannot create
// std::vector larger than max_size()", and `diff --max-fraction nan` fails every frame,
// identical ones too (a share of differing pixels is never <= nan). So the number options read
// their text whole.
TEST_F(CliTest, NumberOptionsRefuseNan) {
  const std::string scene = quote(kScenes + "/cubes.toml");
  const std::pair<std::string, std::string> cases[] = {
      {"render " + scene + " --fps nan -o x.mp4", "--fps: must be a number from 0.001 to 1000"},
      {"export " + scene + " --fps nan -o x.glb", "--fps: must be a number from 0.001 to 1000"},
      {"render " + scene + " --fps 1e400 -o x.mp4", "--fps: must be a number from"},
      {"diff a.png b.png --max-fraction nan", "--max-fraction: must be a number from 0 to 1"},
  };
  for (const auto& [args, message] : cases) {
    EXPECT_EQ(run(args), 2) << args;
    ASSERT_FALSE(errorLines().empty()) << args;
    EXPECT_NE(errorLines()[0].find("voxfall: error: " + message), std::string::npos) << err_;
  }
}

TEST_F(CliTest, BadSceneIsOneErrorLineNamingFileAndLine) {
  const std::string scene = write("bad.toml", "[simulation]\nduration = 2.0\nfsp = 30\n");
  EXPECT_EQ(run("simulate " + quote(scene)), 1);
  const auto errors = errorLines();
  ASSERT_EQ(errors.size(), 1u) << err_;
  EXPECT_EQ(errors[0].rfind("voxfall: error: " + scene + ":3:1: unknown key 'fsp'", 0), 0u)
      << errors[0];
  EXPECT_NE(errors[0].find("did you mean 'fps'?"), std::string::npos) << errors[0];
  EXPECT_TRUE(out_.empty()) << out_;
}

TEST_F(CliTest, MissingSceneFileIsAnError) {
  EXPECT_EQ(run("simulate " + quote((dir_ / "none.toml").string())), 1);
  EXPECT_EQ(errorLines().size(), 1u) << err_;
}

TEST_F(CliTest, UnwritableOutputFailsBeforeSimulatingAndLeavesNothing) {
  const std::string cubes = quote(kScenes + "/cubes.toml");
  // Missing folders are created (as by every command), but not under a plain file.
  write("plain_file", "x");
  const fs::path underFile = dir_ / "plain_file" / "run.csv";
  EXPECT_NE(run("simulate " + cubes + " --quiet --csv " + quote(underFile.string())), 0);
  ASSERT_EQ(errorLines().size(), 1u) << err_;
  EXPECT_NE(errorLines()[0].find(underFile.string()), std::string::npos) << err_;
  EXPECT_TRUE(out_.empty()) << "ran anyway: " << out_;

  // A folder where the summary should go: the CSV, valid on its own, is not left behind either.
  EXPECT_NE(run("simulate " + cubes + " --quiet --csv " + quote((dir_ / "out/a.csv").string()) +
                " --summary " + quote((dir_ / "out").string())),
            0);
  EXPECT_EQ(errorLines().size(), 1u) << err_;
  EXPECT_TRUE(fs::is_empty(dir_ / "out")) << "something was left in " << (dir_ / "out");
}

TEST_F(CliTest, CubesCsvAndSummary) {
  const fs::path csv = dir_ / "out" / "cubes.csv", json = dir_ / "out" / "cubes.json";
  ASSERT_EQ(run("simulate " + quote(kScenes + "/cubes.toml") + " --quiet --csv " +
                quote(csv.string()) + " --summary " + quote(json.string())),
            0)
      << err_;
  EXPECT_TRUE(err_.empty()) << "--quiet printed: " << err_;
  // Only the two outputs: no temporary file remains.
  int files = 0;
  for (const auto& e : fs::directory_iterator(dir_ / "out")) {
    (void)e;
    ++files;
  }
  EXPECT_EQ(files, 2);

  // Summary: every key, frames = floor(2 s * 30 fps) + 1, a 16-hex-digit checksum.
  const std::string summary = readFile(json);
  for (const char* key :
       {"scene", "frames", "steps", "dt_min", "dt_max", "wall_seconds", "sphere_tests", "contacts",
        "max_penetration_body_body", "max_penetration_body_ground", "tunnelled", "kinetic_energy",
        "potential_energy", "checksum"}) {
    EXPECT_NE(summary.find(std::string("\"").append(key).append("\":")), std::string::npos)
        << "missing key " << key << " in\n"
        << summary;
  }
  EXPECT_NE(summary.find("\"scene\": \"cubes\""), std::string::npos) << summary;
  EXPECT_NE(summary.find("\"frames\": 61,"), std::string::npos) << summary;
  std::smatch m;
  ASSERT_TRUE(std::regex_search(summary, m, std::regex("\"checksum\": \"([0-9a-f]{16})\"")))
      << summary;
  // The human summary on stdout ends with the same checksum.
  const std::string checksumLine = std::string("checksum ").append(m[1].str());
  EXPECT_NE(out_.find(checksumLine), std::string::npos) << out_;

  // CSV: the header, then one row per active body per frame (both cubes, all 61 frames),
  // 16 fields each, frames in order.
  const auto rows = lines(readFile(csv));
  ASSERT_FALSE(rows.empty());
  EXPECT_EQ(rows[0], "frame,time,body,x,y,z,qw,qx,qy,qz,vx,vy,vz,wx,wy,wz");
  EXPECT_EQ(rows.size(), 1u + 2u * 61u);
  for (std::size_t i = 1; i < rows.size(); ++i) {
    EXPECT_EQ(std::count(rows[i].begin(), rows[i].end(), ','), 15) << rows[i];
    const int frame = std::stoi(rows[i]);
    EXPECT_EQ(frame, static_cast<int>((i - 1) / 2)) << rows[i];
  }
  // Frame 60 is at t = 2 s exactly.
  EXPECT_EQ(rows.back().rfind("60,2,", 0), 0u) << rows.back();
}

// Rock fall outputs: a cube sliding off the east edge of a flat 20 m DEM (moved by `offset`)
// and one at rest. The run ends when both are settled (stop = "all_at_rest"), long before its
// duration; the outcomes name one left and one stopped, in the DEM's own coordinates.
TEST_F(CliTest, RockfallOutcomesCsvAndGeoJsonAndStopWhenSettled) {
  std::string grid = "ncols 21\nnrows 21\nxllcenter 100\nyllcenter 0\ncellsize 1\n";
  for (int r = 0; r < 21; ++r) {
    for (int i = 0; i < 21; ++i) grid += "0 ";
    grid += "\n";
  }
  write("flat.asc", grid);
  std::filesystem::copy_file(kScenes + "/meshes/cube.obj", dir_ / "cube.obj");
  const std::string scene =
      write("slide.toml",
            "[simulation]\nduration = 30\nlevel = 3\nfps = 10\nstop = \"all_at_rest\"\n"
            "[ground]\nheightfield = \"flat.asc\"\noffset = [-100, 0, 0]\nmaterial = \"bedrock\"\n"
            "[shapes.c]\nmesh = \"cube.obj\"\nscale = 0.3\nmass = 50\n"
            "[[bodies]]\nshape = \"c\"\nposition = [15, 10, 1]\nvelocity = [12, 0, 0]\ndrop_height "
            "= 0.0\n"
            "[[bodies]]\nshape = \"c\"\nposition = [5, 10, 1]\ndrop_height = 0.0\n");
  const fs::path csv = dir_ / "out" / "rocks.csv", geo = dir_ / "out" / "rocks.geojson";
  ASSERT_EQ(run("simulate " + quote(scene) + " -q --outcomes " + quote(csv.string())), 0) << err_;
  EXPECT_NE(err_.find("voxfall: warning: body 0 left the terrain grid at t = "), std::string::npos)
      << err_;
  std::smatch m;
  ASSERT_TRUE(std::regex_search(out_, m,
                                std::regex("rocks: 1 stopped, 1 left the terrain, 0 buried, "
                                           "0 still moving \\(t = ([0-9.]+) s\\)")))
      << out_;
  EXPECT_LT(std::stod(m[1].str()), 10.0);  // ended when settled, not at 30 s
  EXPECT_EQ(err_.find("still moving"), std::string::npos) << err_;  // none was
  const auto rows = lines(readFile(csv));
  ASSERT_EQ(rows.size(), 3u);
  EXPECT_EQ(rows[0].rfind("body,state,release_time_s,release_x,", 0), 0u) << rows[0];
  EXPECT_TRUE(rows[0].ends_with(",max_jump_height_m,bounces")) << rows[0];
  EXPECT_EQ(rows[1].rfind("0,left,", 0), 0u) << rows[1];
  EXPECT_EQ(rows[2].rfind("1,stopped,", 0), 0u) << rows[2];
  // The cube set down at rest never left the ground: no bounce (ground_law.cpp).
  EXPECT_TRUE(rows[2].ends_with(",0")) << rows[2];
  // DEM coordinates: the release of body 0 at world x = 15 is x = 115 in the file's frame.
  EXPECT_EQ(rows[1].find(",115.0"), std::string("0,left,0.000000").size()) << rows[1];
  ASSERT_EQ(run("simulate " + quote(scene) + " -q --outcomes " + quote(geo.string())), 0) << err_;
  const std::string g = readFile(geo);
  EXPECT_NE(g.find("\"FeatureCollection\""), std::string::npos);
  EXPECT_NE(g.find("\"LineString\""), std::string::npos);
  EXPECT_NE(g.find("\"state\": \"left\""), std::string::npos) << g.substr(0, 400);
  EXPECT_NE(g.find("\"bounces\": 0"), std::string::npos) << g.substr(0, 400);

  // Cut off at 0.5 s, before either cube has been still for the rest criterion's 1 s: both
  // outcomes say "moving", and the run warns with that count and the file's name.
  const std::string cut = write(
      "cut.toml", readFile(scene).replace(readFile(scene).find("duration = 30"),
                                          std::string("duration = 30").size(), "duration = 0.5"));
  ASSERT_EQ(run("simulate " + quote(cut) + " -q -y --outcomes " + quote(csv.string())), 0) << err_;
  int moving = 0;
  for (const std::string& row : lines(readFile(csv)))
    moving += row.find(",moving,") != std::string::npos;
  EXPECT_EQ(moving, 2);
  EXPECT_NE(err_.find("voxfall: warning: 2 of 2 rocks were still moving at the end (t = 0.4"),
            std::string::npos)
      << err_;
  EXPECT_NE(err_.find("; " + csv.string() + " records them where they were then"),
            std::string::npos)
      << err_;
}

TEST_F(CliTest, OverridesChangeTheRunAndRunsRepeat) {
  const std::string cubes = quote(kScenes + "/cubes.toml");
  auto checksum = [&](const std::string& extra) {
    EXPECT_EQ(run("simulate " + cubes + " --quiet " + extra), 0) << err_;
    std::smatch m;
    std::regex_search(out_, m, std::regex("checksum ([0-9a-f]{16})"));
    return m.size() > 1 ? m[1].str() : std::string();
  };
  const std::string a = checksum("--level 2");
  EXPECT_EQ(a.size(), 16u);
  EXPECT_EQ(checksum("--level 2"), a);  // deterministic
  EXPECT_NE(checksum("--level 2 --step 1/600"), a);
  EXPECT_EQ(checksum("--level 2 --threads 2"), a);  // threads change no bit (world_test)
  EXPECT_EQ(run("simulate " + cubes + " --quiet --threads 0"), 2) << "threads must be >= 1";
}

// --size is parsed once, in one place (render/cli/options.cpp): a capital X means the same as
// x, and anything else that is not WxH is a usage error, never a size half taken from the scene.
TEST_F(CliTest, SizeWithACapitalXIsThatSizeAndMalformedSizesAreUsageErrors) {
  const std::string cubes = quote(kScenes + "/cubes.toml");
  const fs::path png = dir_ / "out" / "one.png";
  ASSERT_EQ(run("render " + cubes + " --quiet --frames 0:0 --size 64X48 -o " + quote(png.string())),
            0)
      << err_;
  // PNG: the IHDR chunk's width and height, big-endian, at bytes 16..23.
  const std::string bytes = readFile(png);
  ASSERT_GE(bytes.size(), 24u);
  const auto be32 = [&](std::size_t at) {
    std::uint32_t v = 0;
    for (std::size_t i = 0; i < 4; ++i) v = (v << 8) | static_cast<unsigned char>(bytes[at + i]);
    return v;
  };
  EXPECT_EQ(be32(16), 64u);
  EXPECT_EQ(be32(20), 48u);
  for (const char* bad : {"64x", "x48", "64x48x2", "64*48", "0x48", "64x99999"}) {
    EXPECT_EQ(run("render " + cubes + " --quiet --frames 0:0 --size " + bad + " -o x.png"), 2)
        << bad;
    EXPECT_EQ(errorLines().size(), 1u) << err_;
  }
}

// --- Runaway limits and mesh repair (sim/run_guard.h, sim/geometry/mesh_repair.h) ---

// One 0.2 m cube (a mesh written next to the scene) with the given body and [simulation] lines.
std::string cubeScene(const std::string& simulation, const std::string& body) {
  return "[simulation]\nduration = 1.0\nlevel = 2\n" + simulation +
         "\n[ground]\nplane = 0.0\n[shapes.cube]\nmesh = \"" + kScenes +
         "/meshes/cube.obj\"\nscale = 0.2\ndensity = 800\n[[bodies]]\nshape = \"cube\"\n" + body +
         "\n";
}

// --fps is checked as the scene's fps is: a million seconds at 1 frame a second is a scene,
// at 1000 frames a second it is 1e9 frames (and at 1e7 s, 1e10: unchecked, render's frame
// count overflows int and it says the scene's frames are "0:-2147483648").
TEST_F(CliTest, AnFpsOverrideMakingTooManyFramesIsRefusedByName) {
  std::string text = cubeScene("fps = 1.0", "position = [0.0, 0.0, 0.1]");
  text.replace(text.find("duration = 1.0"), 14, "duration = 1e7");
  const std::string scene = write("long.toml", text);
  for (const std::string command : {"render", "export"}) {
    EXPECT_EQ(run(command + " " + quote(scene) + " --fps 1000 --quiet -o " +
                  quote((dir_ / "out" / (command == "render" ? "x.mp4" : "x.glb")).string())),
              1)
        << command;
    ASSERT_EQ(errorLines().size(), 1u) << err_;
    EXPECT_EQ(errorLines()[0],
              "voxfall: error: --fps: 1000 frames per second over the scene's 1e+07 s make 1e+10 "
              "frames; at most 1e+07 are supported");
  }
  EXPECT_FALSE(fs::exists(dir_ / "out" / "x.mp4"));
  EXPECT_FALSE(fs::exists(dir_ / "out" / "x.glb"));
}

TEST_F(CliTest, AnAbsurdSpeedIsRefusedBeforeTheRun) {
  const std::string scene =
      write("fast.toml", cubeScene("", "position = [0.0, 0.0, 1.0]\nvelocity = [1e30, 0.0, 0.0]"));
  const std::string csv = (dir_ / "out" / "fast.csv").string();
  EXPECT_EQ(run("simulate " + quote(scene) + " --quiet --csv " + quote(csv)), 1);
  ASSERT_EQ(errorLines().size(), 1u) << err_;
  // The [[bodies]] table is on line 11 of the scene.
  EXPECT_NE(errorLines()[0].find("fast.toml:11:1: body 0 (shape 'cube') starts at 1e+30 m/s"),
            std::string::npos)
      << err_;
  EXPECT_NE(errorLines()[0].find("--max-speed"), std::string::npos) << err_;
  EXPECT_FALSE(fs::exists(csv));
  // With the speed allowed, the step count is next: the 1e-6 s floor of the step needs 1e6
  // steps for 1 s.
  EXPECT_EQ(run("simulate " + quote(scene) + " --quiet --max-speed 2e30 --max-steps 1000"), 1);
  ASSERT_EQ(errorLines().size(), 1u) << err_;
  EXPECT_NE(errorLines()[0].find("needs about 1e+06 steps over 1 s, over the limit of 1000"),
            std::string::npos)
      << err_;
}

TEST_F(CliTest, ARunawayStopsWithExit1AndKeepsTheFramesSoFar) {
  // Dropped from 10 m with max_speed = 5 m/s: the speed g t passes 5 m/s at t = 0.51 s, so the
  // run stops there; frames 0..15 (t <= 0.5 s, 30 fps) were complete and stay in the CSV.
  const std::string scene =
      write("drop.toml", cubeScene("max_speed = 5.0", "position = [0.0, 0.0, 10.0]"));
  const std::string csv = (dir_ / "out" / "drop.csv").string();
  const std::string summary = (dir_ / "out" / "drop.json").string();
  EXPECT_EQ(run("simulate " + quote(scene) + " --quiet --csv " + quote(csv) + " --summary " +
                quote(summary)),
            1);
  ASSERT_EQ(errorLines().size(), 1u) << err_;
  EXPECT_NE(errorLines()[0].find("drop.toml: body 0 (shape 'cube') at t = 0.5"), std::string::npos)
      << err_;
  EXPECT_NE(errorLines()[0].find("exceeds the limit of 5 m/s"), std::string::npos) << err_;
  const auto rows = lines(readFile(csv));
  ASSERT_EQ(rows.size(), 1u + 16u);
  for (std::size_t i = 1; i < rows.size(); ++i) {
    EXPECT_EQ(std::stoi(rows[i]), static_cast<int>(i - 1));
    EXPECT_EQ(std::count(rows[i].begin(), rows[i].end(), ','), 15) << rows[i];
  }
  EXPECT_FALSE(fs::exists(summary)) << "no summary of a run that did not finish";
  // A bake of the same run keeps the complete frames 0..15 (t <= 0.5 s) and renders the last.
  const std::string bake = (dir_ / "out" / "drop.bake").string();
  EXPECT_EQ(run("simulate " + quote(scene) + " --quiet --bake " + quote(bake)), 1);
  ASSERT_TRUE(fs::exists(bake)) << err_;
  const std::string png = (dir_ / "out" / "last.png").string();
  EXPECT_EQ(run("render " + quote(bake) + " --quiet --frames 15:15 --size 64x48 -o " + quote(png)),
            0)
      << err_;
  EXPECT_TRUE(fs::exists(png));
  EXPECT_EQ(run("render " + quote(bake) + " --quiet --frames 16:16 --size 64x48 -o x.png"), 1)
      << "frame 16 lies after the runaway: not in the bake";
  // The same scene with the bound raised on the command line runs to the end.
  EXPECT_EQ(run("simulate " + quote(scene) + " --quiet --max-speed 100"), 0) << err_;
}

TEST_F(CliTest, AnOpenMeshNamesRepairAndRepairSaysWhatItDid) {
  // A 0.2 x 0.2 x 1 box with the top face's second triangle missing (a 2.3 % patch).
  write("holed.obj",
        "v 0 0 0\nv 0.2 0 0\nv 0 0.2 0\nv 0.2 0.2 0\nv 0 0 1\nv 0.2 0 1\nv 0 0.2 1\nv 0.2 0.2 1\n"
        "f 1 3 4\nf 1 4 2\nf 5 6 8\nf 1 2 6\nf 1 6 5\nf 3 7 8\nf 3 8 4\n"
        "f 1 5 7\nf 1 7 3\nf 2 4 8\nf 2 8 6\n");
  const std::string scene = write("holed.toml",
                                  "[simulation]\nduration = 0.2\nlevel = 2\n[ground]\nplane = 0.0\n"
                                  "[shapes.box]\nmesh = \"holed.obj\"\ndensity = 800\n"
                                  "[[bodies]]\nshape = \"box\"\nposition = [0.0, 0.0, 0.5]\n");
  EXPECT_EQ(run("simulate " + quote(scene) + " --quiet"), 1);
  ASSERT_EQ(errorLines().size(), 1u) << err_;
  EXPECT_NE(errorLines()[0].find("holed.obj: mesh is not closed"), std::string::npos) << err_;
  EXPECT_NE(errorLines()[0].find("--repair"), std::string::npos) << err_;
  EXPECT_EQ(run("simulate " + quote(scene) + " --quiet --repair"), 0) << err_;
  EXPECT_NE(err_.find("holed.obj: repaired: filled 1 hole with 1 triangle"), std::string::npos)
      << err_;
}

}  // namespace

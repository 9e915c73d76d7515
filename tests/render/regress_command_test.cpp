// `voxfall regress` end to end, in scratch suites built from the committed goldens:
//   - a cube moved by one leaf voxel (0.3/16 m at Lv 4) fails against copies of
//     tests/golden/cubes: the checksum ("the physics changed") and every frame, each failing
//     frame with an expected | actual | diff picture in the report; the unmoved copy passes;
//   - missing goldens are reported (not a crash), --update creates them through temporary
//     files, rewrites only what fails, and the next run passes;
//   - `voxfall render --frames k:k` writes the golden's exact bytes, and the frames do not
//     depend on llvmpipe's thread count (LP_NUM_THREADS=1: bit-identical);
//   - suite.toml errors are one line naming file:line:column; a broken case fails alone;
//   - exit codes 0 / 1 / 2.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>

#include "render/output/png_writer.h"
#include "render_test_util.h"

namespace vf {
namespace {

namespace fs = std::filesystem;

const fs::path kSource = VOXFALL_SOURCE_DIR;

std::string readFile(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

void writeFile(const fs::path& p, const std::string& text) {
  fs::create_directories(p.parent_path());
  std::ofstream(p) << text;
}

int count(const std::string& text, const std::string& what) {
  int n = 0;
  for (std::size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

// scenes/cubes.toml as a scene file elsewhere (mesh path made absolute), optionally with cube A
// moved along x.
std::string cubesScene(double moveX = 0) {
  std::string text = readFile(kSource / "scenes/cubes.toml");
  const auto replace = [&](const std::string& from, const std::string& to) {
    const std::size_t at = text.find(from);
    EXPECT_NE(at, std::string::npos) << "scenes/cubes.toml changed: " << from;
    if (at != std::string::npos) text.replace(at, from.size(), to);
  };
  replace("mesh = \"meshes/cube.obj\"",
          "mesh = \"" + (kSource / "scenes/meshes/cube.obj").string() + "\"");
  if (moveX != 0) {
    char moved[64];
    std::snprintf(moved, sizeof moved, "position = [%.17g, 0.0, 0.15]", moveX);
    replace("position = [0.0, 0.0, 0.15]", moved);
  }
  return text;
}

const char* kCubesCase =
    "[[case]]\nname = \"cubes\"\nscene = \"cubes.toml\"\nframes = [0, 6, 60]\n"
    "size = [320, 180]\n";

class RegressCommand : public ::testing::Test {
 protected:
  RegressCommand()
      : dir_("regress_cmd_" +
             std::string(::testing::UnitTest::GetInstance()->current_test_info()->name())) {}

  // Runs `[env] voxfall ARGS` in the scratch folder; returns the exit code.
  int runVoxfall(const std::string& args, const std::string& env = "") {
    const std::string cmd = "cd '" + dir_.path().string() + "' && env -u DISPLAY " + env + " '" +
                            std::string(VOXFALL_EXE) + "' " + args +
                            " >stdout.txt 2>stderr.txt </dev/null";
    const int status = std::system(cmd.c_str());
    out_ = readFile(dir_.path() / "stdout.txt");
    err_ = readFile(dir_.path() / "stderr.txt");
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  }
  int run(const std::string& args, const std::string& env = "") {
    return runVoxfall("regress " + args, env);
  }
  fs::path path(const std::string& name) const { return dir_.path() / name; }
  // A suite in `name` holding cubes.toml (moved by moveX) and copies of the committed goldens.
  void cubesSuite(const std::string& name, double moveX) {
    writeFile(path(name) / "suite.toml", kCubesCase);
    writeFile(path(name) / "cubes.toml", cubesScene(moveX));
    fs::create_directories(path(name) / "cubes");
    for (const auto& e : fs::directory_iterator(kSource / "tests/golden/cubes"))
      fs::copy_file(e.path(), path(name) / "cubes" / e.path().filename());
  }

  test::ScratchDir dir_;
  std::string out_, err_;
};

TEST_F(RegressCommand, ABodyMovedByOneLeafVoxelFailsAgainstTheGoldens) {
  cubesSuite("same", 0);
  ASSERT_EQ(run("same -o report_same"), 0) << out_ << err_;  // the control
  EXPECT_EQ(count(out_, ": ok    max diff 0/255"), 3) << out_;

  const double leaf = 0.3 / 16;  // cube edge / 2^Lv at Lv 4
  cubesSuite("moved", leaf);
  ASSERT_EQ(run("moved -o report"), 1) << out_ << err_;
  EXPECT_NE(out_.find(": FAIL, golden "), std::string::npos) << out_;
  EXPECT_NE(out_.find("the physics changed"), std::string::npos) << out_;
  // Every frame, frame 0 included: there only the position differs, the physics not yet.
  for (const char* frame : {"frame_0000", "frame_0006", "frame_0060"}) {
    EXPECT_NE(out_.find(std::string(frame) + ".png: FAIL"), std::string::npos) << frame << out_;
    const fs::path picture = path("report/cubes") / (std::string(frame) + "_compare.png");
    ASSERT_TRUE(fs::exists(picture)) << picture;
    const Image composite = readPng(picture.string());
    // expected | actual | diff under labels, and the three crops at 4x under theirs
    const int band = 7 * 2 + 8;
    EXPECT_EQ(composite.width, 3 * 320 + 2 * 4);
    EXPECT_EQ(composite.height, band + 180 + 4 + band + 180);
    // The HTML report's pictures: the golden as it is, the actual frame, the diff.
    const Image expected =
        readPng((path("report/cubes") / (std::string(frame) + "_expected.png")).string());
    EXPECT_EQ(expected.rgb,
              readPng((path("moved/cubes") / (std::string(frame) + ".png")).string()).rgb);
    for (const char* kind : {"_actual.png", "_diff.png"})
      EXPECT_TRUE(fs::exists(path("report/cubes") / (std::string(frame) + kind))) << frame << kind;
  }
  const std::string html = readFile(path("report/index.html"));
  EXPECT_NE(html.find("src=\"cubes/frame_0006_expected.png\""), std::string::npos);
  const std::string report = readFile(path("report/report.txt"));
  EXPECT_NE(report.find("frame_0000.png: FAIL"), std::string::npos) << report;
  EXPECT_NE(report.find("FAIL: 1 case, 0 of 3 frames passed, 1 checksums changed or missing"),
            std::string::npos)
      << report;

  // --update accepts the change: checksum and the three frames rewritten, then it passes, and
  // the report of the failed run is cleared of its pictures.
  ASSERT_EQ(run("moved -o report --update"), 0) << out_ << err_;
  EXPECT_EQ(count(out_, "WRITTEN (was"), 4) << out_;
  ASSERT_EQ(run("moved -o report"), 0) << out_ << err_;
  EXPECT_FALSE(fs::exists(path("report/cubes/frame_0000_compare.png")));
}

// The same move seen by a fixed camera, so that only the cube's own pixels can change (the
// automatic camera above also reframes): still over the default tolerance (measured 0.22% to
// 0.29% of the pixels, against 0.05%), in frame 0, before the physics differs.
TEST_F(RegressCommand, OneLeafVoxelFailsEvenWithAFixedCamera) {
  const std::string camera =
      "\n[camera]\nposition = [2.2, -3.2, 1.3]\nlook_at = [0.4, 0.1, 0.15]\nfov = 40\n";
  writeFile(
      path("s/suite.toml"),
      "[[case]]\nname = \"cubes\"\nscene = \"cubes.toml\"\nframes = [0]\nsize = [320, 180]\n");
  writeFile(path("s/cubes.toml"), cubesScene() + camera);
  ASSERT_EQ(run("s -o r --update"), 0) << out_ << err_;
  for (const double dx : {0.3 / 16, -0.3 / 16}) {
    writeFile(path("s/cubes.toml"), cubesScene(dx) + camera);
    EXPECT_EQ(run("s -o r"), 1) << out_ << err_;
    EXPECT_NE(out_.find("frame_0000.png: FAIL"), std::string::npos) << dx << "\n" << out_;
  }
  // A mask over the whole frame hides the move from the frame (the checksum still fails).
  writeFile(path("s/suite.toml"),
            "[[case]]\nname = \"cubes\"\nscene = \"cubes.toml\"\nframes = [0]\nsize = [320, 180]\n"
            "mask = [[0, 0, 160, 180], [160, 0, 160, 180]]\n");
  EXPECT_EQ(run("s -o r"), 1) << out_ << err_;
  EXPECT_NE(out_.find("frame_0000.png: ok    max diff 0/255, 0.000% of pixels differ (0 of 0 > "
                      "8/255, 57600 masked)"),
            std::string::npos)
      << out_;
  // With the pixel count turned off, a minimum SSIM still sees the move.
  writeFile(path("s/suite.toml"),
            "[[case]]\nname = \"cubes\"\nscene = \"cubes.toml\"\nframes = [0]\nsize = [320, 180]\n"
            "threshold = 255\nmax_fraction = 1.0\nmin_ssim = 0.9999\n");
  EXPECT_EQ(run("s -o r"), 1) << out_ << err_;
  EXPECT_NE(out_.find("frame_0000.png: FAIL"), std::string::npos) << out_;
}

// Cases rendered in two worker processes give the same report files, byte for byte, as one
// process (timings.txt apart, and the JUnit file's time attributes): the same lines, pictures,
// page and XML, in case order.
TEST_F(RegressCommand, JobsGiveTheSameReportBytes) {
  cubesSuite("s", 0.3 / 16);
  writeFile(path("s/same.toml"), cubesScene());
  writeFile(path("s/suite.toml"), std::string(kCubesCase) +
                                      "\n[[case]]\nname = \"same\"\nscene = \"same.toml\"\n"
                                      "frames = [0, 60]\nsize = [160, 90]\n" +
                                      "\n[[case]]\nname = \"broken\"\nscene = \"same.toml\"\n"
                                      "frames = [9999]\n");
  ASSERT_EQ(run("s -o same --update --case same"), 0) << out_ << err_;
  // Both into the folder r (the reports name it), the first then moved aside.
  ASSERT_EQ(run("s -o r --junit r/junit.xml"), 1) << out_ << err_;
  const std::string out1 = out_;
  fs::rename(path("r"), path("r1"));
  ASSERT_EQ(run("s -o r --junit r/junit.xml -j 2"), 1) << out_ << err_;
  const auto withoutTimes = [](std::string text) {
    for (std::size_t at = text.find("time=\""); at != std::string::npos;
         at = text.find("time=\"", at + 1))
      text.erase(at, text.find('"', at + 6) + 1 - at);
    return text;
  };
  EXPECT_EQ(withoutTimes(readFile(path("r1/junit.xml"))),
            withoutTimes(readFile(path("r/junit.xml"))));
  std::vector<std::string> files;
  for (const auto& e : fs::recursive_directory_iterator(path("r1"))) {
    const fs::path rel = fs::relative(e.path(), path("r1"));
    if (!e.is_regular_file() || rel == "timings.txt" || rel == "junit.xml") continue;
    files.push_back(rel.string());
    EXPECT_TRUE(fs::exists(path("r") / rel) && readFile(e.path()) == readFile(path("r") / rel))
        << rel;
  }
  // report.txt, index.html and 4 pictures of each of the 3 failing frames
  EXPECT_EQ(files.size(), 2u + 4 * 3) << ::testing::PrintToString(files);
  // The stdout lines up to the one with the run's time.
  EXPECT_EQ(out1.substr(0, out1.find("report:")), out_.substr(0, out_.find("report:")));
  EXPECT_NE(out_.find("broken (s/suite.toml:"), std::string::npos) << out_;
}

TEST_F(RegressCommand, MissingGoldensAreReportedAndUpdateCreatesThem) {
  writeFile(path("s/suite.toml"),
            "# a user's suite\n[[case]]\nname = \"cubes\"\nscene = \"cubes.toml\"  # the scene\n"
            "frames = [0, 60]\nsize = [160, 90]\n");
  writeFile(path("s/cubes.toml"), cubesScene());
  EXPECT_EQ(run("s -o r"), 1) << out_ << err_;
  EXPECT_EQ(count(out_, "MISSING golden"), 3) << out_;  // the checksum and two frames
  EXPECT_TRUE(fs::exists(path("r/cubes/frame_0060_actual.png")));
  EXPECT_FALSE(fs::exists(path("s/cubes")));

  ASSERT_EQ(run("s -o r --update"), 0) << out_ << err_;
  EXPECT_EQ(count(out_, "WRITTEN (new)"), 3) << out_;
  for (const char* f : {"checksum.txt", "frame_0000.png", "frame_0060.png"})
    EXPECT_TRUE(fs::exists(path("s/cubes") / f)) << f;
  int files = 0;
  for (const auto& e : fs::directory_iterator(path("s/cubes"))) {
    EXPECT_EQ(e.path().string().find("part"), std::string::npos) << "left behind: " << e.path();
    ++files;
  }
  EXPECT_EQ(files, 3);
  EXPECT_EQ(readPng(path("s/cubes/frame_0000.png").string()).width, 160);
  EXPECT_TRUE(
      std::regex_match(readFile(path("s/cubes/checksum.txt")), std::regex("[0-9a-f]{16}\n")));
  EXPECT_EQ(run("s -o r"), 0) << out_;
  EXPECT_FALSE(fs::exists(path("r/cubes/frame_0060_actual.png")));

  // A frame added to the list: only it is written; a golden no case lists is pointed out.
  writeFile(path("s/suite.toml"),
            "[[case]]\nname = \"cubes\"\nscene = \"cubes.toml\"\nframes = [0, 30, 60]\n"
            "size = [160, 90]\n");
  fs::copy_file(path("s/cubes/frame_0000.png"), path("s/cubes/frame_0099.png"));
  ASSERT_EQ(run("s -o r --update"), 0) << out_;
  EXPECT_EQ(count(out_, "WRITTEN"), 1) << out_;
  EXPECT_NE(out_.find("frame_0030.png: WRITTEN (new)"), std::string::npos) << out_;
  EXPECT_NE(out_.find("frame_0099.png: not in suite.toml"), std::string::npos) << out_;
}

TEST_F(RegressCommand, RenderWritesTheGoldensPixels) {
  // `voxfall render --frames k:k` in a new process, long after the goldens were made: the same
  // pixels, byte for byte (regress draws through the same code, and frames repeat exactly).
  // The files differ: render compresses frames faster than regress compresses goldens.
  for (const int k : {0, 6, 60}) {
    const std::string file = expandFramePattern("frame_####.png", k);
    std::string args = "render '";
    args.append((kSource / "scenes/cubes.toml").string());
    args.append("' --size 320x180 -q --frames " + std::to_string(k) + ":" + std::to_string(k));
    args.append(" -o " + file);
    ASSERT_EQ(runVoxfall(args), 0) << err_;
    const Image drawn = readPng(path(file).string());
    const Image golden = readPng((kSource / "tests/golden/cubes" / file).string());
    EXPECT_EQ(drawn.width, golden.width) << file;
    EXPECT_TRUE(drawn.rgb == golden.rgb) << file;
  }
}

TEST_F(RegressCommand, FramesDoNotDependOnTheRasterisersThreadCount) {
  // The committed goldens were made with llvmpipe's default thread count. (Built by append:
  // GCC 12 at -O3 gives a false -Wrestrict on a chain of operator+.)
  std::string args = "'";
  args.append((kSource / "tests/golden").string());
  args.append("' --case cubes -o r");
  ASSERT_EQ(run(args, "LP_NUM_THREADS=1"), 0) << out_ << err_;
  EXPECT_EQ(count(out_, ": ok    max diff 0/255"), 3) << out_;
}

TEST_F(RegressCommand, SuiteErrorsNameFileLineAndColumn) {
  writeFile(path("s/cubes.toml"), cubesScene());
  const std::string suite = path("s/suite.toml").string();
  const auto expectError = [&](const std::string& text, const std::string& where,
                               const std::string& what) {
    writeFile(suite, text);
    EXPECT_EQ(run("s"), 1) << text;
    EXPECT_EQ(count(err_, "voxfall: error:"), 1) << err_;
    const std::string prefix = "voxfall: error: s/suite.toml" + (where.empty() ? "" : ":" + where);
    EXPECT_NE(err_.find(prefix + ": "), std::string::npos) << "for:\n" << text << "got: " << err_;
    EXPECT_NE(err_.find(what), std::string::npos) << err_;
    EXPECT_TRUE(out_.empty()) << out_;
  };
  expectError("[[case]]\nscene = \"cubes.toml\"\nframe = [0]\n", "3:1", "unknown key 'frame'");
  expectError("[[case]]\nscene = \"none.toml\"\nframes = [0]\n", "2:9", "not found");
  expectError("[case]\n", "1:1", "only [[case]] tables");
  expectError("[[case]]\nscene = \"cubes.toml\"\nframes = [0, 1, 0]\n", "3:10", "listed twice");
  expectError("[[case]]\nscene = \"cubes.toml\"\nframes = [0,\n  1\n", "4:5",
              "Error while parsing array");  // toml++ reports where the file ended
  expectError("[[case]]\nscene = \"cubes.toml\"\nframes = [0]\nsize = [320]\n", "4:8",
              "[width, height]");
  expectError("[[case]]\nscene = \"cubes.toml\"\nframes = [0]\nthreshold = 300\n", "4:13",
              "0..255");
  expectError("[[case]]\nscene = \"cubes.toml\"\nframes = [0]\nruns = 0\n", "4:8", "1..1000");
  // nan fails every comparison: it would pass a range check, and then every frame would fail,
  // even an identical one (a share of differing pixels is never <= nan).
  expectError("[[case]]\nscene = \"cubes.toml\"\nframes = [0]\nmax_fraction = nan\n", "4:16",
              "'max_fraction' must be a number in 0..1");
  expectError("[[case]]\nscene = \"cubes.toml\"\nframes = [0]\nmask = [[0, 0, 10]]\n", "4:9",
              "'mask' must be a list of rectangles [x, y, width, height]");
  expectError("[[case]]\nscene = \"cubes.toml\"\nframes = [0]\nmask = [[0, 0, 0, 5]]\n", "4:16",
              "'mask width' must be an integer in 1..");
  expectError("min_ssim = 1.5\n[[case]]\nscene = \"cubes.toml\"\nframes = [0]\n", "1:12",
              "'min_ssim' must be a number in 0..1 (a mean SSIM)");
  expectError("[[case]]\nscene = \"cubes.toml\"\n", "1", "needs 'frames");
  expectError(
      "[[case]]\nscene = \"cubes.toml\"\nframes = [0]\n\n[[case]]\nscene = "
      "\"cubes.toml\"\nframes = [1]\n",
      "5", "a second case named 'cubes'");
  expectError("# nothing\n", "", "no [[case]]");
}

TEST_F(RegressCommand, ABrokenCaseFailsAloneAndUsageExits2) {
  writeFile(path("s/cubes.toml"), cubesScene());
  writeFile(path("s/suite.toml"),
            "[[case]]\nname = \"late\"\nscene = \"cubes.toml\"\nframes = [61]\nsize = [64, 36]\n"
            "\n[[case]]\nscene = \"cubes.toml\"\nframes = [0]\nsize = [64, 36]\n");
  ASSERT_EQ(run("s --update"), 1) << out_ << err_;
  EXPECT_NE(out_.find("late (s/suite.toml:1): ERROR"), std::string::npos) << out_;
  EXPECT_NE(out_.find("outside the scene's frames 0:60"), std::string::npos) << out_;
  // A mask rectangle off the frame fails its case, naming the rectangle and the frame size.
  writeFile(path("s/suite.toml"),
            "[[case]]\nscene = \"cubes.toml\"\nframes = [0]\n"
            "size = [64, 36]\nmask = [[60, 0, 5, 5]]\n");
  ASSERT_EQ(run("s"), 1) << out_ << err_;
  EXPECT_NE(out_.find("s/suite.toml:5:8: mask rectangle [60, 0, 5, 5] reaches outside the 64x36 "
                      "frame"),
            std::string::npos)
      << out_;
  EXPECT_TRUE(fs::exists(path("s/cubes/frame_0000.png")));  // the other case ran
  EXPECT_TRUE(fs::exists(path("out/regress/report.txt")));  // the default report folder

  // 'runs' draws an ensemble's realisations; on a scene without [ensemble] it is that case's
  // error, naming the case's line, and nothing is written for it.
  writeFile(path("s/suite.toml"),
            "[[case]]\nname = \"many\"\nscene = \"cubes.toml\"\nframes = [0]\nruns = 3\n");
  ASSERT_EQ(run("s --update"), 1) << out_ << err_;
  EXPECT_NE(out_.find("many (s/suite.toml:1): ERROR s/suite.toml:1: 'runs' is for a scene with "
                      "an [ensemble] table, and s/cubes.toml has none"),
            std::string::npos)
      << out_;
  EXPECT_FALSE(fs::exists(path("s/many")));

  EXPECT_EQ(run("no_such_suite"), 1);
  EXPECT_NE(err_.find("no_such_suite: not a folder"), std::string::npos) << err_;
  EXPECT_EQ(run("s --case nope"), 1);
  EXPECT_EQ(run(""), 2);
  EXPECT_EQ(run("s --gl vulkan"), 2);
}

}  // namespace
}  // namespace vf

// `voxfall diff` end to end on synthetic PNGs (written with writePng): exit codes (0 within
// tolerance, 1 over it or bad input, 2 usage), the per-frame lines, the tolerance options, the
// diff image, and folders matched by name (missing frames fail, extra ones are only listed).
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "render/output/png_writer.h"
#include "render_test_util.h"

namespace vf {
namespace {

namespace fs = std::filesystem;

std::string readFile(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// 100 x 100 mid grey; `changed` pixels of the top row turned white: each 0.01% of the image.
Image frame(int changed = 0) {
  Image image(100, 100);
  for (auto& v : image.rgb) v = 128;
  for (int x = 0; x < changed; ++x) {
    std::uint8_t* p = image.pixel(x, 0);
    p[0] = p[1] = p[2] = 255;
  }
  return image;
}

class DiffCommand : public ::testing::Test {
 protected:
  DiffCommand()
      : dir_("diff_cmd_" +
             std::string(::testing::UnitTest::GetInstance()->current_test_info()->name())) {}
  int run(const std::string& args) {
    const std::string cmd = "cd '" + dir_.path().string() + "' && '" + std::string(VOXFALL_EXE) +
                            "' diff " + args + " >stdout.txt 2>stderr.txt </dev/null";
    const int status = std::system(cmd.c_str());
    out_ = readFile(dir_.path() / "stdout.txt");
    err_ = readFile(dir_.path() / "stderr.txt");
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  }
  void write(const std::string& name, const Image& image) {
    fs::create_directories((dir_.path() / name).parent_path());
    writePng(dir_.file(name), image);
  }
  bool says(const std::string& text) const { return out_.find(text) != std::string::npos; }

  test::ScratchDir dir_;
  std::string out_, err_;
};

TEST_F(DiffCommand, IdenticalFilesPass) {
  write("a.png", frame());
  write("b.png", frame());
  EXPECT_EQ(run("a.png b.png"), 0) << out_ << err_;
  EXPECT_TRUE(says("b.png: ok")) << out_;
  EXPECT_TRUE(says("max diff 0/255, 0.000% of pixels differ (0 of 10000 > 8/255), PSNR inf"))
      << out_;
}

TEST_F(DiffCommand, DefaultToleranceAndItsOptions) {
  write("a.png", frame());
  write("five.png", frame(5));  // 0.05%: at the default limit, passes
  write("six.png", frame(6));   // 0.06%: over
  EXPECT_EQ(run("a.png five.png"), 0) << out_;
  EXPECT_EQ(run("a.png six.png"), 1) << out_;
  EXPECT_TRUE(says("six.png: FAIL")) << out_;
  EXPECT_TRUE(says("max diff 127/255, 0.060% of pixels differ (6 of 10000 > 8/255)")) << out_;
  EXPECT_TRUE(says("over tolerance")) << out_;
  EXPECT_EQ(run("a.png six.png --max-fraction 0.001"), 0) << out_;
  EXPECT_EQ(run("a.png six.png --threshold 127"), 0) << out_;  // 127 is not more than 127
  EXPECT_EQ(run("a.png six.png -t 126"), 1) << out_;
}

TEST_F(DiffCommand, WritesTheDiffImage) {
  write("a.png", frame());
  write("b.png", frame(6));
  EXPECT_EQ(run("a.png b.png --out d.png"), 1) << out_;
  const Image d = readPng(dir_.file("d.png"));
  ASSERT_EQ(d.width, 100);
  EXPECT_GE(d.pixel(0, 0)[0], 128);  // changed: red
  EXPECT_EQ(d.pixel(0, 0)[1], 0);
  EXPECT_EQ(d.pixel(50, 50)[0], d.pixel(50, 50)[1]);  // unchanged: grey
  EXPECT_TRUE(says("diff image: d.png")) << out_;
}

TEST_F(DiffCommand, DifferentSizesFail) {
  write("a.png", frame());
  write("b.png", Image(100, 50));
  EXPECT_EQ(run("a.png b.png"), 1);
  EXPECT_TRUE(says("size differs: expected 100x100, actual 100x50")) << out_;
}

TEST_F(DiffCommand, FoldersMatchedByName) {
  write("exp/f_0001.png", frame());
  write("exp/f_0002.png", frame());
  write("exp/f_0003.png", frame());
  write("act/f_0001.png", frame());
  write("act/f_0002.png", frame(20));
  write("act/f_0004.png", frame());
  EXPECT_EQ(run("exp act --out diffs"), 1) << out_ << err_;
  EXPECT_TRUE(says("f_0001.png: ok")) << out_;
  EXPECT_TRUE(says("f_0002.png: FAIL")) << out_;
  EXPECT_TRUE(says("f_0003.png: MISSING in act")) << out_;
  EXPECT_TRUE(says("f_0004.png: only in act (not compared)")) << out_;
  EXPECT_TRUE(says("1 of 3 frames within tolerance, 1 over, 1 missing")) << out_;
  EXPECT_TRUE(fs::exists(dir_.path() / "diffs/f_0001.png"));
  EXPECT_TRUE(fs::exists(dir_.path() / "diffs/f_0002.png"));
  // Only extra frames: still a pass.
  fs::remove(dir_.path() / "exp/f_0002.png");
  fs::remove(dir_.path() / "exp/f_0003.png");
  EXPECT_EQ(run("exp act"), 0) << out_;
}

TEST_F(DiffCommand, BadInputExits1UsageExits2) {
  write("a.png", frame());
  fs::create_directories(dir_.path() / "folder");
  std::ofstream(dir_.file("text.png")) << "not a png";
  EXPECT_EQ(run("a.png none.png"), 1);
  EXPECT_NE(err_.find("voxfall: error: none.png: no such file or folder"), std::string::npos)
      << err_;
  EXPECT_EQ(run("a.png text.png"), 1);
  EXPECT_NE(err_.find("text.png: cannot read PNG"), std::string::npos) << err_;
  EXPECT_EQ(run("a.png folder"), 1);
  EXPECT_NE(err_.find("not a file with a folder"), std::string::npos) << err_;
  EXPECT_EQ(run("folder folder"), 1);  // no frames to compare
  EXPECT_EQ(run("a.png"), 2);
  EXPECT_EQ(run("a.png a.png --threshold 300"), 2);
  EXPECT_EQ(run("a.png a.png --max-fraction 2"), 2);
}

// The diff image never replaces a compared image: `--out` naming EXPECTED or ACTUAL (a file, or
// for folders the folder whose frames the diff images would be named after) is refused before
// anything is written, and both images are left as they were.
TEST_F(DiffCommand, TheDiffNeverOverwritesWhatItCompares) {
  write("a.png", frame());
  write("b.png", frame(20));
  const std::string a = readFile(dir_.path() / "a.png"), b = readFile(dir_.path() / "b.png");
  EXPECT_EQ(run("a.png b.png --out a.png"), 1);
  EXPECT_NE(err_.find("voxfall: error: a.png: is an input of this run"), std::string::npos) << err_;
  EXPECT_EQ(out_, "");  // refused before comparing
  EXPECT_EQ(run("a.png b.png --out ./b.png"), 1);
  EXPECT_EQ(readFile(dir_.path() / "a.png"), a);
  EXPECT_EQ(readFile(dir_.path() / "b.png"), b);

  write("exp/f_0001.png", frame());
  write("act/f_0001.png", frame(20));
  const std::string golden = readFile(dir_.path() / "exp/f_0001.png");
  const std::string actual = readFile(dir_.path() / "act/f_0001.png");
  EXPECT_EQ(run("exp act --out exp"), 1);
  EXPECT_NE(err_.find("exp: is the folder of the compared frames (exp)"), std::string::npos)
      << err_;
  EXPECT_EQ(run("exp act --out act/"), 1);
  EXPECT_NE(err_.find("the diff images would overwrite them"), std::string::npos) << err_;
  EXPECT_EQ(readFile(dir_.path() / "exp/f_0001.png"), golden);
  EXPECT_EQ(readFile(dir_.path() / "act/f_0001.png"), actual);
  // Another folder still gets the diff image, and replaces an earlier one.
  EXPECT_EQ(run("exp act --out diffs"), 1);
  EXPECT_EQ(run("exp act --out diffs"), 1);
  EXPECT_TRUE(fs::exists(dir_.path() / "diffs/f_0001.png"));
}

}  // namespace
}  // namespace vf

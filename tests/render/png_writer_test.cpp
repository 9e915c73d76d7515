// PNG writer: round trip through libpng's reader (an independent code path: the simplified
// read API, not our writer), '#' pattern expansion, failures that leave nothing behind.
#include "render/output/png_writer.h"

#include <gtest/gtest.h>
#include <png.h>

#include <cstring>
#include <filesystem>
#include <fstream>

#include "render_test_util.h"
#include "sim/core/error.h"

namespace vf {
namespace {

namespace fs = std::filesystem;

Image testPattern(int w, int h) {
  Image image(w, h);
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      std::uint8_t* p = image.pixel(x, y);
      p[0] = static_cast<std::uint8_t>(x * 13 + y);
      p[1] = static_cast<std::uint8_t>(y * 29);
      p[2] = static_cast<std::uint8_t>((x ^ y) * 7);
    }
  }
  image.pixel(0, 0)[0] = 255;  // a marked top-left corner: catches a flipped image
  return image;
}

Image readPng(const std::string& path) {
  png_image png;
  std::memset(&png, 0, sizeof png);
  png.version = PNG_IMAGE_VERSION;
  if (!png_image_begin_read_from_file(&png, path.c_str())) {
    ADD_FAILURE() << "libpng cannot read " << path << ": " << png.message;
    return Image();
  }
  png.format = PNG_FORMAT_RGB;
  Image image(static_cast<int>(png.width), static_cast<int>(png.height));
  if (!png_image_finish_read(&png, nullptr, image.rgb.data(), 0, nullptr)) {
    ADD_FAILURE() << "libpng cannot decode " << path << ": " << png.message;
  }
  return image;
}

TEST(PngWriter, WrittenPixelsReadBackIdentical) {
  test::ScratchDir dir("png_roundtrip");
  const Image image = testPattern(37, 21);  // odd width: rows are not 4-byte aligned
  const std::string path = dir.file("frame.png");
  writePng(path, image);
  const Image back = readPng(path);
  EXPECT_EQ(back.width, 37);
  EXPECT_EQ(back.height, 21);
  EXPECT_EQ(back.rgb, image.rgb);
  EXPECT_FALSE(fs::exists(path + ".part"));
}

TEST(PngWriter, HashRunBecomesZeroPaddedFrameNumber) {
  EXPECT_EQ(expandFramePattern("out/cubes/frame_####.png", 7), "out/cubes/frame_0007.png");
  EXPECT_EQ(expandFramePattern("f_##.png", 123), "f_123.png");  // wider than the run: whole
  EXPECT_EQ(expandFramePattern("f_#.png", 0), "f_0.png");
  EXPECT_EQ(expandFramePattern("a#b/f_###.png", 42), "a#b/f_042.png");  // the last run only
  EXPECT_EQ(expandFramePattern("still.png", 5), "still.png");
}

TEST(PngWriter, SequenceWriterNamesEachFrame) {
  test::ScratchDir dir("png_sequence");
  PngSequenceWriter writer(dir.file("f_###.png"));
  const Image image = testPattern(4, 4);
  writer.write(3, image);
  writer.write(30, image);
  writer.finish();
  EXPECT_EQ(writer.framesWritten(), 2);
  EXPECT_TRUE(fs::exists(dir.file("f_003.png")));
  EXPECT_TRUE(fs::exists(dir.file("f_030.png")));
}

TEST(PngWriter, UnwritablePathIsAClearErrorAndLeavesNoFile) {
  test::ScratchDir dir("png_unwritable");
  const Image image = testPattern(4, 4);
  // A folder that does not exist, and a "folder" that is a regular file.
  const std::string missing = dir.file("no_such_folder/frame.png");
  std::ofstream(dir.file("plain_file")) << "x";
  const std::string underFile = dir.file("plain_file/frame.png");
  for (const std::string& path : {missing, underFile}) {
    try {
      writePng(path, image);
      ADD_FAILURE() << "wrote " << path;
    } catch (const InputError& e) {
      EXPECT_EQ(e.where(), path);
      EXPECT_NE(std::string(e.what()).find("cannot write PNG"), std::string::npos) << e.what();
    }
    EXPECT_FALSE(fs::exists(path));
    EXPECT_FALSE(fs::exists(path + ".part"));
  }
  // Nothing but the plain file was created in the scratch folder.
  int entries = 0;
  for ([[maybe_unused]] const auto& e : fs::directory_iterator(dir.path())) ++entries;
  EXPECT_EQ(entries, 1);
}

TEST(FrameSink, OutputKindFollowsThePath) {
  EXPECT_EQ(outputKind("out/a.mp4"), OutputKind::mp4);
  EXPECT_EQ(outputKind("out/A.MP4"), OutputKind::mp4);
  EXPECT_EQ(outputKind("out/f_####.png"), OutputKind::pngSequence);
  EXPECT_EQ(outputKind("out/still.png"), OutputKind::png);
  EXPECT_THROW(outputKind("out/a.avi"), InputError);
  EXPECT_THROW(outputKind("out/f_####.jpg"), InputError);
  // A single PNG cannot hold several frames.
  EXPECT_THROW(openFrameSink("out/still.png", VideoSettings{}, 2), InputError);
}

}  // namespace
}  // namespace vf

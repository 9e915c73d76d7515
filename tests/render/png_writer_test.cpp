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
  EXPECT_EQ(test::partialFiles(dir.path()), 0);
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
  PngSequenceWriter writer(dir.file("f_###.png"), replaceOutputs());
  const Image image = testPattern(4, 4);
  writer.write(3, image);
  writer.write(30, image);
  writer.finish();
  EXPECT_EQ(writer.framesWritten(), 2);
  EXPECT_TRUE(fs::exists(dir.file("f_003.png")));
  EXPECT_TRUE(fs::exists(dir.file("f_030.png")));
}

TEST(PngWriter, MissingFoldersAreCreatedAndAFileForAFolderIsAClearError) {
  test::ScratchDir dir("png_unwritable");
  const Image image = testPattern(4, 4);
  // Output folders are created, as for every output (output_file.h).
  writePng(dir.file("new/folder/frame.png"), image);
  EXPECT_EQ(readPng(dir.file("new/folder/frame.png")).rgb, image.rgb);
  // A "folder" that is a regular file cannot be.
  std::ofstream(dir.file("plain_file")) << "x";
  const std::string underFile = dir.file("plain_file/frame.png");
  try {
    writePng(underFile, image);
    ADD_FAILURE() << "wrote " << underFile;
  } catch (const InputError& e) {
    EXPECT_EQ(e.where(), underFile);
    EXPECT_NE(std::string(e.what()).find("cannot create the folder"), std::string::npos)
        << e.what();
  }
  EXPECT_EQ(test::partialFiles(dir.path()), 0);
  EXPECT_EQ(test::partialFiles(dir.path() / "new/folder"), 0);
}

TEST(FrameSink, OutputKindFollowsThePath) {
  EXPECT_EQ(outputKind("out/a.mp4"), OutputKind::mp4);
  EXPECT_EQ(outputKind("out/A.MP4"), OutputKind::mp4);
  EXPECT_EQ(outputKind("out/f_####.png"), OutputKind::pngSequence);
  EXPECT_EQ(outputKind("out/still.png"), OutputKind::png);
  EXPECT_THROW(outputKind("out/a.avi"), InputError);
  EXPECT_THROW(outputKind("out/f_####.jpg"), InputError);
  // A single PNG cannot hold several frames.
  EXPECT_THROW(openFrameSink("out/still.png", VideoSettings{}, 0, 1, replaceOutputs()), InputError);
}

}  // namespace
}  // namespace vf

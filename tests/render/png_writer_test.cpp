// PNG writer: round trip through libpng's reader (an independent code path: the simplified
// read API, not our writer), '#' pattern expansion, failures that leave nothing behind.
#include "render/output/png_writer.h"

#include <gtest/gtest.h>
#include <png.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "render_test_util.h"
#include "sim/core/error.h"
#include "tests/support/voxfall_command.h"

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

// The alpha plane, read back as RGBA by libpng.
TEST(PngWriter, AnAlphaPlaneIsWrittenAsRgbaAndReadsBack) {
  test::ScratchDir dir("png_alpha");
  Image image = testPattern(23, 9);
  image.alpha.resize(23 * 9);
  for (std::size_t i = 0; i < image.alpha.size(); ++i)
    image.alpha[i] = static_cast<std::uint8_t>(i * 37);
  for (const PngCompression c : {PngCompression::small, PngCompression::fast}) {
    const std::string path = dir.file(c == PngCompression::fast ? "fast.png" : "small.png");
    writePng(path, image, replaceOutputs(), c);
    png_image png;
    std::memset(&png, 0, sizeof png);
    png.version = PNG_IMAGE_VERSION;
    ASSERT_TRUE(png_image_begin_read_from_file(&png, path.c_str())) << png.message;
    EXPECT_NE(png.format & PNG_FORMAT_FLAG_ALPHA, 0u) << "no alpha channel in the file";
    png.format = PNG_FORMAT_RGBA;
    std::vector<std::uint8_t> rgba(PNG_IMAGE_SIZE(png));
    ASSERT_TRUE(png_image_finish_read(&png, nullptr, rgba.data(), 0, nullptr)) << png.message;
    ASSERT_EQ(rgba.size(), image.alpha.size() * 4);
    for (std::size_t i = 0; i < image.alpha.size(); ++i) {
      ASSERT_EQ(rgba[4 * i + 3], image.alpha[i]) << "pixel " << i;
      for (int c3 = 0; c3 < 3; ++c3) ASSERT_EQ(rgba[4 * i + c3], image.rgb[3 * i + c3]) << i;
    }
  }
}

// Frames compressed on 1 and on 3 workers: the same files, byte for byte, each the bytes of
// compressing that frame alone, all written by finish(); frames written in order.
TEST(PngWriter, SequenceBytesDoNotDependOnTheWorkers) {
  test::ScratchDir dir("png_workers");
  std::vector<Image> frames;
  for (int k = 0; k < 9; ++k) {
    Image image = testPattern(64, 40);
    image.pixel(k, k)[1] = 7;  // each frame its own
    frames.push_back(image);
  }
  for (const int threads : {1, 3}) {
    PngSequenceWriter writer(dir.file("t" + std::to_string(threads) + "/f_#.png"), replaceOutputs(),
                             threads);
    EXPECT_EQ(writer.threads(), threads);
    for (int k = 0; k < 9; ++k) writer.write(k, frames[static_cast<std::size_t>(k)]);
    writer.finish();
    EXPECT_EQ(writer.framesWritten(), 9);
  }
  for (int k = 0; k < 9; ++k) {
    const std::string one = test::readFile(dir.path() / ("t1/f_" + std::to_string(k) + ".png"));
    const std::string three = test::readFile(dir.path() / ("t3/f_" + std::to_string(k) + ".png"));
    ASSERT_FALSE(one.empty()) << k;
    EXPECT_EQ(one, three) << "frame " << k;
    const std::vector<std::uint8_t> alone =
        encodePng(frames[static_cast<std::size_t>(k)], PngCompression::fast, "frame");
    EXPECT_EQ(one, std::string(alone.begin(), alone.end())) << "frame " << k;
    EXPECT_EQ(readPng(dir.file("t3/f_" + std::to_string(k) + ".png")).rgb,
              frames[static_cast<std::size_t>(k)].rgb);
  }
}

// A frame that cannot be written is reported, and nothing after it is written.
TEST(PngWriter, ASequenceThatCannotBeWrittenFailsOnce) {
  test::ScratchDir dir("png_fail");
  std::ofstream(dir.file("plain_file")) << "x";
  PngSequenceWriter writer(dir.file("plain_file/f_#.png"), replaceOutputs(), 2);
  const Image image = testPattern(8, 8);
  EXPECT_THROW(
      {
        for (int k = 0; k < 6; ++k) writer.write(k, image);
        writer.finish();
      },
      InputError);
  EXPECT_THROW(writer.finish(), InputError);  // the same failure, again
  EXPECT_EQ(test::partialFiles(dir.path()), 0);
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

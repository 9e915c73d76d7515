// image_diff: metrics against hand computations on synthetic images (the threshold is "more
// than", the fraction limit inclusive, PSNR from its definition), the pictures' layout and
// colours, and readPng on the PNG kinds other tools write (grey, alpha, 16-bit), written here
// with libpng directly so the reader is not only checked against voxfall's own writer.
#include "render/output/image_diff.h"

#include <gtest/gtest.h>
#include <png.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <vector>

#include "render/output/png_writer.h"
#include "render_test_util.h"
#include "sim/core/error.h"

namespace vf {
namespace {

Image flat(int w, int h, std::uint8_t r, std::uint8_t g, std::uint8_t b) {
  Image image(w, h);
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      std::uint8_t* p = image.pixel(x, y);
      p[0] = r;
      p[1] = g;
      p[2] = b;
    }
  }
  return image;
}

TEST(ImageDiff, IdenticalImages) {
  const Image a = flat(10, 10, 10, 20, 30);
  const DiffMetrics m = compareImages(a, a, 8);
  EXPECT_TRUE(m.identical());
  EXPECT_EQ(m.maxChannelDiff, 0);
  EXPECT_EQ(m.differingPixels, 0);
  EXPECT_EQ(m.pixels, 100);
  EXPECT_TRUE(std::isinf(m.psnr));
  EXPECT_TRUE(withinTolerance(m, DiffTolerance{}));
}

TEST(ImageDiff, APixelDiffersOnlyAboveTheThreshold) {
  const Image a = flat(10, 10, 100, 100, 100);
  Image b = a;
  b.pixel(3, 4)[1] = 108;  // 8: not more than 8
  EXPECT_EQ(compareImages(a, b, 8).differingPixels, 0);
  EXPECT_EQ(compareImages(a, b, 8).maxChannelDiff, 8);
  b.pixel(3, 4)[1] = 91;  // 9, the other way
  const DiffMetrics m = compareImages(a, b, 8);
  EXPECT_EQ(m.differingPixels, 1);
  EXPECT_EQ(m.maxChannelDiff, 9);
  EXPECT_DOUBLE_EQ(m.differingFraction, 0.01);
}

TEST(ImageDiff, PsnrByHand) {
  // One channel of one pixel of 100 off by 10: MSE = 100 / 300, PSNR = 10 log10(255^2 * 3).
  const Image a = flat(10, 10, 50, 50, 50);
  Image b = a;
  b.pixel(0, 0)[2] = 60;
  EXPECT_NEAR(compareImages(a, b, 8).psnr, 10 * std::log10(255.0 * 255.0 * 3), 1e-9);
}

TEST(ImageDiff, FractionLimitIsInclusive) {
  const Image a = flat(100, 100, 0, 0, 0);
  Image b = a;
  for (int i = 0; i < 5; ++i) b.pixel(i, 0)[0] = 255;  // 5 of 10000 = 0.05%
  const DiffTolerance tolerance{8, 0.0005, {}};
  EXPECT_TRUE(withinTolerance(compareImages(a, b, 8), tolerance));
  b.pixel(5, 0)[0] = 255;  // 6 of 10000
  EXPECT_FALSE(withinTolerance(compareImages(a, b, 8), tolerance));
  EXPECT_NE(describe(compareImages(a, b, 8), a, b).find("6 of 10000 > 8/255"), std::string::npos)
      << describe(compareImages(a, b, 8), a, b);
}

TEST(ImageDiff, DifferentSizesFail) {
  const Image a = flat(10, 10, 0, 0, 0), b = flat(10, 11, 0, 0, 0);
  const DiffMetrics m = compareImages(a, b, 255);
  EXPECT_FALSE(m.sameSize);
  EXPECT_FALSE(withinTolerance(m, DiffTolerance{255, 1.0, {}}));
  EXPECT_EQ(describe(m, a, b), "size differs: expected 10x10, actual 10x11");
}

TEST(ImageDiff, DiffImageColours) {
  const Image a = flat(4, 1, 200, 200, 200);
  Image b = a;
  b.pixel(1, 0)[0] = 203;  // under the threshold: blue
  b.pixel(2, 0)[0] = 220;  // over: red
  b.pixel(3, 0)[0] = 0;    // far over: brighter red
  const Image d = diffImage(a, b, 8);
  ASSERT_EQ(d.width, 4);
  ASSERT_EQ(d.height, 1);
  const std::uint8_t* same = d.pixel(0, 0);
  EXPECT_TRUE(same[0] == same[1] && same[1] == same[2]) << "unchanged pixels are grey";
  EXPECT_LT(same[0], 128) << "and dim";
  const std::uint8_t* under = d.pixel(1, 0);
  EXPECT_GT(under[2], under[0]);
  const std::uint8_t* over = d.pixel(2, 0);
  const std::uint8_t* farOver = d.pixel(3, 0);
  EXPECT_GE(over[0], 128);
  EXPECT_EQ(over[1], 0);
  EXPECT_EQ(over[2], 0);
  EXPECT_GT(farOver[0], over[0]);
}

TEST(ImageDiff, DiffImageOfASmallerActualIsRedOutsideIt) {
  const Image a = flat(4, 2, 50, 50, 50), b = flat(2, 2, 50, 50, 50);
  const Image d = diffImage(a, b, 8);
  EXPECT_EQ(d.pixel(3, 1)[0], 255);
  EXPECT_EQ(d.pixel(3, 1)[1], 0);
  EXPECT_EQ(d.pixel(1, 1)[0], d.pixel(1, 1)[1]);  // inside: grey
}

// --- readPng ---------------------------------------------------------------------------------

void writeWithLibpng(const std::string& path, int w, int h, png_uint_32 format,
                     const std::vector<std::uint8_t>& data) {
  png_image png;
  std::memset(&png, 0, sizeof png);
  png.version = PNG_IMAGE_VERSION;
  png.width = static_cast<png_uint_32>(w);
  png.height = static_cast<png_uint_32>(h);
  png.format = format;
  ASSERT_NE(png_image_write_to_file(&png, path.c_str(), 0, data.data(), 0, nullptr), 0)
      << png.message;
}

TEST(ReadPng, RoundTripOfTheWriter) {
  test::ScratchDir dir("read_png_roundtrip");
  Image image(7, 5);
  for (std::size_t i = 0; i < image.rgb.size(); ++i)
    image.rgb[i] = static_cast<std::uint8_t>(i * 37);
  writePng(dir.file("a.png"), image);
  const Image back = readPng(dir.file("a.png"));
  EXPECT_EQ(back.width, 7);
  EXPECT_EQ(back.height, 5);
  EXPECT_EQ(back.rgb, image.rgb);
}

TEST(ReadPng, GreyAndAlphaBecomeRgbOnBlack) {
  test::ScratchDir dir("read_png_ga");
  // Grey + alpha: an opaque 200, a fully transparent 255.
  writeWithLibpng(dir.file("ga.png"), 2, 1, PNG_FORMAT_GA, {200, 255, 255, 0});
  const Image ga = readPng(dir.file("ga.png"));
  ASSERT_EQ(ga.width, 2);
  EXPECT_EQ(ga.pixel(0, 0)[0], 200);
  EXPECT_EQ(ga.pixel(0, 0)[1], 200);
  EXPECT_EQ(ga.pixel(0, 0)[2], 200);
  EXPECT_EQ(ga.pixel(1, 0)[0], 0);
  EXPECT_EQ(ga.pixel(1, 0)[2], 0);
  // RGBA, opaque: the colour as written.
  writeWithLibpng(dir.file("rgba.png"), 1, 1, PNG_FORMAT_RGBA, {10, 20, 30, 255});
  const Image rgba = readPng(dir.file("rgba.png"));
  EXPECT_EQ(rgba.pixel(0, 0)[0], 10);
  EXPECT_EQ(rgba.pixel(0, 0)[1], 20);
  EXPECT_EQ(rgba.pixel(0, 0)[2], 30);
}

TEST(ReadPng, SixteenBitLinearBecomesEightBitSrgb) {
  test::ScratchDir dir("read_png_16");
  const std::vector<png_uint_16> linear = {65535, 0, 65535, 0, 0, 0};
  png_image png;
  std::memset(&png, 0, sizeof png);
  png.version = PNG_IMAGE_VERSION;
  png.width = 2;
  png.height = 1;
  png.format = PNG_FORMAT_LINEAR_RGB;
  ASSERT_NE(
      png_image_write_to_file(&png, dir.file("l16.png").c_str(), 0, linear.data(), 0, nullptr), 0)
      << png.message;
  const Image image = readPng(dir.file("l16.png"));
  ASSERT_EQ(image.width, 2);
  EXPECT_EQ(image.pixel(0, 0)[0], 255);
  EXPECT_EQ(image.pixel(0, 0)[1], 0);
  EXPECT_EQ(image.pixel(0, 0)[2], 255);
  EXPECT_EQ(image.pixel(1, 0)[0], 0);
}

TEST(ReadPng, MissingOrBrokenFilesAreInputErrors) {
  test::ScratchDir dir("read_png_bad");
  try {
    readPng(dir.file("none.png"));
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.where(), dir.file("none.png"));
  }
  std::ofstream(dir.file("text.png")) << "not a png\n";
  EXPECT_THROW(readPng(dir.file("text.png")), InputError);
}

}  // namespace
}  // namespace vf

// The perceptual metric, masks, the changed-region crop and the labelled compare picture
// (render/output/ssim.h, pixel_mask.h, compare_image.h, bitmap_font.h), against hand
// computations and an independent direct sum on synthetic images.
#include "render/output/compare_image.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "render/output/bitmap_font.h"
#include "render/output/image_diff.h"
#include "render/output/ssim.h"

namespace vf {
namespace {

Image grey(int w, int h, std::uint8_t v) {
  Image image(w, h);
  std::fill(image.rgb.begin(), image.rgb.end(), v);
  return image;
}

void setGrey(Image& image, int x, int y, std::uint8_t v) {
  std::uint8_t* p = image.pixel(x, y);
  p[0] = p[1] = p[2] = v;
}

// --- SSIM ------------------------------------------------------------------------------------

// Two flat images: both variances and the covariance are 0, so SSIM is the luminance term
// alone, (2 mx my + C1) / (mx^2 + my^2 + C1) with C1 = (0.01 * 255)^2 = 6.5025; for 100 and
// 110: 22006.5025 / 22106.5025.
TEST(Ssim, FlatImagesByHand) {
  EXPECT_NEAR(meanSsim(grey(11, 11, 100), grey(11, 11, 110)), 22006.5025 / 22106.5025, 1e-12);
  EXPECT_NEAR(meanSsim(grey(40, 30, 100), grey(40, 30, 110)), 22006.5025 / 22106.5025, 1e-12);
  EXPECT_EQ(meanSsim(grey(40, 30, 77), grey(40, 30, 77)), 1.0);
}

// An 11 x 11 pair is exactly one window: the SSIM computed here directly from the paper's
// definition (2-D Gaussian weights, sigma 1.5, normalised; weighted means, variances and
// covariance) must equal the separable implementation's.
TEST(Ssim, OneWindowAgainstTheDefinition) {
  Image a = grey(11, 11, 0), b = grey(11, 11, 0);
  for (int y = 0; y < 11; ++y)
    for (int x = 0; x < 11; ++x) {
      setGrey(a, x, y, static_cast<std::uint8_t>((x * 23 + y * 7) % 256));
      setGrey(b, x, y, static_cast<std::uint8_t>((x * 23 + y * 7 + (x == y ? 40 : 0)) % 256));
    }
  double w[11][11], sum = 0;
  for (int y = 0; y < 11; ++y)
    for (int x = 0; x < 11; ++x)
      sum += w[y][x] = std::exp(-((x - 5) * (x - 5) + (y - 5) * (y - 5)) / (2 * 1.5 * 1.5));
  double mx = 0, my = 0;
  for (int y = 0; y < 11; ++y)
    for (int x = 0; x < 11; ++x) {
      mx += w[y][x] / sum * a.pixel(x, y)[0];  // grey: the luma is the value itself
      my += w[y][x] / sum * b.pixel(x, y)[0];
    }
  double vx = 0, vy = 0, cxy = 0;
  for (int y = 0; y < 11; ++y)
    for (int x = 0; x < 11; ++x) {
      const double dx = a.pixel(x, y)[0] - mx, dy = b.pixel(x, y)[0] - my;
      vx += w[y][x] / sum * dx * dx, vy += w[y][x] / sum * dy * dy, cxy += w[y][x] / sum * dx * dy;
    }
  const double c1 = 6.5025, c2 = 58.5225;  // (0.01 * 255)^2, (0.03 * 255)^2
  const double expected =
      (2 * mx * my + c1) * (2 * cxy + c2) / ((mx * mx + my * my + c1) * (vx + vy + c2));
  EXPECT_NEAR(meanSsim(a, b), expected, 1e-9);
  EXPECT_LT(expected, 0.99);  // the case is not trivial
}

// A shift by one pixel of a sharp edge: few pixels differ, structure does (the point of SSIM).
TEST(Ssim, FallsForMovedStructureMoreThanForAFaintShift) {
  Image a = grey(64, 64, 40), moved = grey(64, 64, 40), faint = grey(64, 64, 40);
  for (int y = 20; y < 44; ++y)
    for (int x = 20; x < 44; ++x) setGrey(a, x, y, 220), setGrey(moved, x + 2, y, 220);
  for (int y = 0; y < 64; ++y)
    for (int x = 0; x < 64; ++x) setGrey(faint, x, y, a.pixel(x, y)[0] + 3);
  EXPECT_LT(meanSsim(a, moved), meanSsim(a, faint));
}

// --- masks -----------------------------------------------------------------------------------

// The images differ in a 5 x 4 rectangle and in one pixel just outside it: a mask of exactly
// that rectangle leaves the one pixel, one a pixel smaller leaves a row more.
TEST(Mask, HidesExactlyItsRectangle) {
  const Image a = grey(20, 10, 50);
  Image b = a;
  for (int y = 3; y < 7; ++y)
    for (int x = 4; x < 9; ++x) setGrey(b, x, y, 200);
  setGrey(b, 9, 3, 200);  // right of the rectangle
  const DiffMetrics all = compareImages(a, b, 8);
  EXPECT_EQ(all.differingPixels, 21);
  const DiffMetrics masked = compareImages(a, b, 8, {{4, 3, 5, 4}});
  EXPECT_EQ(masked.differingPixels, 1);
  EXPECT_EQ(masked.maskedPixels, 20);
  EXPECT_EQ(masked.pixels, 200 - 20);
  const DiffMetrics smaller = compareImages(a, b, 8, {{4, 3, 5, 3}});
  EXPECT_EQ(smaller.differingPixels, 6);
  // Masked alone, the images are the same to every metric.
  Image c = a;
  for (int y = 3; y < 7; ++y)
    for (int x = 4; x < 9; ++x) setGrey(c, x, y, 200);
  const DiffMetrics hidden = compareImages(a, c, 8, {{4, 3, 5, 4}});
  EXPECT_TRUE(hidden.identical());
  EXPECT_EQ(hidden.ssim, 1.0);
  EXPECT_NE(describe(masked, a, b).find(", 20 masked"), std::string::npos);
}

TEST(Mask, MinSsimJudgesOnlyWhenSet) {
  DiffMetrics m;
  m.differingFraction = 0;
  m.ssim = 0.95;
  DiffTolerance t;
  EXPECT_TRUE(withinTolerance(m, t));
  t.minSsim = 0.96;
  EXPECT_FALSE(withinTolerance(m, t));
  t.minSsim = 0.95;
  EXPECT_TRUE(withinTolerance(m, t));
}

// --- the changed region and the compare picture -----------------------------------------------

TEST(ChangedRegion, TheWindowHoldingMostOfTheChange) {
  const Image a = grey(80, 40, 30);
  Image b = a;
  setGrey(b, 3, 3, 255);  // a lone pixel far away
  for (int y = 30; y < 33; ++y)
    for (int x = 60; x < 66; ++x) setGrey(b, x, y, 255);
  const auto r = changedRegion(a, b, 8);
  ASSERT_TRUE(r.has_value());
  EXPECT_EQ(r->width, 20);  // 80 / 4
  EXPECT_EQ(r->height, 10);
  // The block (columns 60-65, rows 30-32) inside the window and centred in it: its middle,
  // column 63 and row 31, at the window's middle.
  EXPECT_EQ(r->x, 63 - 10);
  EXPECT_EQ(r->y, 31 - 5);
  // Near the border the window stays inside the image.
  Image corner = a;
  setGrey(corner, 79, 39, 255);
  const auto c = changedRegion(a, corner, 8);
  ASSERT_TRUE(c.has_value());
  EXPECT_EQ(c->x + c->width, 80);
  EXPECT_EQ(c->y + c->height, 40);
  // Masking the block leaves the lone pixel; identical images have no region.
  const auto lone = changedRegion(a, b, 8, {{60, 30, 6, 3}});
  ASSERT_TRUE(lone.has_value());
  EXPECT_TRUE(lone->contains(3, 3));
  EXPECT_FALSE(changedRegion(a, a, 8).has_value());
  // Under the threshold only: the pixels that differ at all.
  Image faint = a;
  setGrey(faint, 70, 5, 33);
  const auto f = changedRegion(a, faint, 8);
  ASSERT_TRUE(f.has_value());
  EXPECT_TRUE(f->contains(70, 5));
}

TEST(ComparePicture, PanelsUnderLabelsAndEnlargedCrops) {
  const Image e = grey(40, 20, 10), a = grey(40, 20, 20), d = grey(40, 20, 30);
  const PixelRect crop{8, 4, 10, 5};
  const Image p = comparePicture(e, a, d, crop);
  const int band = 7 * 2 + 8, gap = 4;
  EXPECT_EQ(p.width, 3 * 40 + 2 * gap);
  EXPECT_EQ(p.height, band + 20 + gap + band + 5 * 4);
  EXPECT_EQ(p.pixel(0, band + 19)[0], 10);                // expected, bottom-left
  EXPECT_EQ(p.pixel(40 + gap, band)[0], 20);              // actual
  EXPECT_EQ(p.pixel(2 * (40 + gap) + 39, band)[0], 30);   // diff
  EXPECT_EQ(p.pixel(crop.x - 1, band + crop.y)[0], 255);  // the crop outlined in yellow
  const int row2 = band + 20 + gap + band;
  EXPECT_EQ(p.pixel(0, row2)[0], 10);         // expected enlarged
  EXPECT_EQ(p.pixel(39, row2 + 19)[0], 10);   // 10 x 5 at 4x: 40 x 20
  EXPECT_EQ(p.pixel(40 + gap, row2)[0], 20);  // actual enlarged
  // Without a crop: one row.
  EXPECT_EQ(comparePicture(e, a, d, std::nullopt).height, band + 20);
}

TEST(ComparePicture, EnlargedKeepsEveryPixelAsABlock) {
  Image image = grey(4, 4, 0);
  setGrey(image, 2, 1, 200);
  const Image z = enlarged(image, {1, 1, 2, 2}, 4);
  ASSERT_EQ(z.width, 8);
  EXPECT_EQ(z.pixel(4, 0)[0], 200);
  EXPECT_EQ(z.pixel(7, 3)[0], 200);
  EXPECT_EQ(z.pixel(3, 0)[0], 0);
  EXPECT_EQ(z.pixel(4, 4)[0], 0);
}

TEST(BitmapFont, CoversTheLabelsAndDrawsAGlyph) {
  for (const char* label : {"EXPECTED 4x", "ACTUAL", "DIFF", "t = 1.25 s", "(0/1) 50% A_Z:-"})
    EXPECT_TRUE(fontCovers(label)) << label;
  EXPECT_FALSE(fontCovers("lowercase a"));
  EXPECT_EQ(textWidth("AB", 2), 2 * 6 * 2 - 2);
  Image image = grey(12, 14, 0);
  drawText(image, 0, 0, "I", 2, {255, 255, 255});
  EXPECT_EQ(image.pixel(4, 0)[0], 255);  // the top bar of I: columns 1-3 of 5, at 2x
  EXPECT_EQ(image.pixel(0, 0)[0], 0);
  EXPECT_EQ(image.pixel(4, 6)[0], 255);  // the stem
}

}  // namespace
}  // namespace vf

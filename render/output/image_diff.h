// Comparing two frames for visual regression tests (`voxfall diff`, `voxfall regress`): the
// numbers (largest channel difference, fraction of differing pixels, PSNR), a verdict under a
// tolerance, and pictures a person can judge at a glance. Plain code on Image, no I/O.
//
// The tolerance is two numbers, as in Filament's renderdiff: a pixel "differs" when one of its
// channels differs by more than `threshold` (of 255), and a comparison fails when more than
// `maxFraction` of the pixels differ. One number alone does not work: a max-difference limit
// fails on a single rounding outlier at an anti-aliased edge, and a PSNR limit passes a small
// body that moved by a few pixels in a large frame (its edges are a tiny share of the error).
// PSNR is reported for the reader, not judged. SSIM (ssim.h) is reported too, and judged only
// where a tolerance asks for a minimum. Masked rectangles (pixel_mask.h) are left out of every
// number.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "render/image.h"
#include "render/output/pixel_mask.h"

namespace vf {

// The defaults come from measurement (numbers in image_diff.cpp): llvmpipe's rounding
// differences stay 14 times below them; a body moved by one leaf voxel is 4 times above them in
// every frame; a sun turned by 5 degrees in azimuth fails every frame, in elevation or by 2
// degrees the frames where its shadows are large.
struct DiffTolerance {
  int threshold = 8;              // channel difference (0..255) above which a pixel differs
  double maxFraction = 0.0005;    // share of pixels (0..1) allowed to differ: 0.05%
  std::optional<double> minSsim;  // when set, a frame whose mean SSIM is lower fails too
};

struct DiffMetrics {
  int width = 0;  // of the expected image
  int height = 0;
  bool sameSize = true;              // false: nothing else below is meaningful but `differing`
  int maxChannelDiff = 0;            // 0..255, over all pixels and channels
  std::int64_t differingPixels = 0;  // pixels with a channel difference > threshold
  std::int64_t pixels = 0;           // pixels compared (width * height, less masked ones)
  std::int64_t maskedPixels = 0;     // pixels inside the mask, not compared
  double differingFraction = 0;      // differingPixels / pixels
  double psnr = 0;    // dB over all channels, 10 log10(255^2 / MSE); +infinity when identical
  int threshold = 8;  // the threshold the differing pixels were counted with
  double ssim = 0;    // mean SSIM of the luma (ssim.h); 0 when the sizes differ

  bool identical() const { return sameSize && maxChannelDiff == 0; }
};

// Compares `actual` with `expected` pixel by pixel, leaving out the pixels of `mask`. Images of
// different sizes are not compared: sameSize is false and every pixel counts as differing.
DiffMetrics compareImages(const Image& expected, const Image& actual, int threshold,
                          const PixelMask& mask = {});

// True when the metrics are within the tolerance (same size, differing fraction <= maxFraction,
// and SSIM >= minSsim where one is set).
bool withinTolerance(const DiffMetrics& metrics, const DiffTolerance& tolerance);

// One line for people: "max diff 3/255, 0.012% of pixels differ (7 of 57600 > 16/255), PSNR
// 51.2 dB, SSIM 0.99871" (and ", 400 masked" when a mask hid pixels), or what differs in size.
std::string describe(const DiffMetrics& metrics, const Image& expected, const Image& actual);

// Where the frames differ, at the size of `expected`: the expected image in dim grey, pixels
// over the threshold in red (brighter for larger differences), pixels that differ but within
// the threshold in blue, so rounding noise and a real change look different. Of different
// sizes: the area outside either image is red. Masked pixels are drawn darker, unmarked.
Image diffImage(const Image& expected, const Image& actual, int threshold,
                const PixelMask& mask = {});

}  // namespace vf

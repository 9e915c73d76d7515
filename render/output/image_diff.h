// Comparing two frames for visual regression tests (`voxfall diff`, `voxfall regress`): the
// numbers (largest channel difference, fraction of differing pixels, PSNR), a verdict under a
// tolerance, and pictures a person can judge at a glance. Plain code on Image, no I/O.
//
// The tolerance is two numbers, as in Filament's renderdiff: a pixel "differs" when one of its
// channels differs by more than `threshold` (of 255), and a comparison fails when more than
// `maxFraction` of the pixels differ. One number alone does not work: a max-difference limit
// fails on a single rounding outlier at an anti-aliased edge, and a PSNR limit passes a small
// body that moved by a few pixels in a large frame (its edges are a tiny share of the error).
// PSNR is reported for the reader, not judged.
#pragma once

#include <cstdint>
#include <string>

#include "render/image.h"

namespace vf {

// The defaults come from measurement (numbers in image_diff.cpp): llvmpipe's rounding
// differences stay 14 times below them; a body moved by one leaf voxel is 4 times above them in
// every frame; a sun turned by 5 degrees fails every frame, by 2 degrees the frames where its
// shadows are large.
struct DiffTolerance {
  int threshold = 8;            // channel difference (0..255) above which a pixel differs
  double maxFraction = 0.0005;  // share of pixels (0..1) allowed to differ: 0.05%
};

struct DiffMetrics {
  int width = 0;  // of the expected image
  int height = 0;
  bool sameSize = true;              // false: nothing else below is meaningful but `differing`
  int maxChannelDiff = 0;            // 0..255, over all pixels and channels
  std::int64_t differingPixels = 0;  // pixels with a channel difference > threshold
  std::int64_t pixels = 0;           // pixels compared (width * height)
  double differingFraction = 0;      // differingPixels / pixels
  double psnr = 0;    // dB over all channels, 10 log10(255^2 / MSE); +infinity when identical
  int threshold = 8;  // the threshold the differing pixels were counted with

  bool identical() const { return sameSize && maxChannelDiff == 0; }
};

// Compares `actual` with `expected` pixel by pixel. Images of different sizes are not compared:
// sameSize is false and every pixel counts as differing.
DiffMetrics compareImages(const Image& expected, const Image& actual, int threshold);

// True when the metrics are within the tolerance (same size, differing fraction <= maxFraction).
bool withinTolerance(const DiffMetrics& metrics, const DiffTolerance& tolerance);

// One line for people: "max diff 3/255, 0.012% of pixels differ (7 of 57600 > 16/255), PSNR
// 51.2 dB", or what differs in size.
std::string describe(const DiffMetrics& metrics, const Image& expected, const Image& actual);

// Where the frames differ, at the size of `expected`: the expected image in dim grey, pixels
// over the threshold in red (brighter for larger differences), pixels that differ but within
// the threshold in blue, so rounding noise and a real change look different. Of different
// sizes: the area outside either image is red.
Image diffImage(const Image& expected, const Image& actual, int threshold);

// expected | actual | diff side by side on a dark background with a 4-pixel gap, tops aligned:
// the one picture a reviewer looks at when a frame fails.
Image sideBySide(const Image& expected, const Image& actual, const Image& diff);

}  // namespace vf

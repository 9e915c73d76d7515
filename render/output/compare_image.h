// The picture a reviewer looks at when a frame fails (`voxfall regress`), labelled and zoomed:
// expected | actual | diff at frame size under the labels EXPECTED, ACTUAL, DIFF, and below
// them the same three cropped around the change and enlarged 4x, so that a rock that moved by
// five pixels in a 1280x720 frame is plain to see. The crop is outlined on the full panels.
#pragma once

#include <optional>

#include "render/image.h"
#include "render/output/pixel_mask.h"

namespace vf {

constexpr int kCompareZoom = 4;

// The crop that shows the change best: a window of ceil(width / zoom) x ceil(height / zoom)
// pixels (so that, enlarged, it is the size of the frame) placed where it holds the most pixels
// differing by more than `threshold`, or, when none does, by anything at all (ties: the topmost,
// then the leftmost), then moved to centre those pixels. Masked pixels do not count. Empty when
// the images are equal outside the mask or differ in size.
std::optional<PixelRect> changedRegion(const Image& expected, const Image& actual, int threshold,
                                       const PixelMask& mask = {}, int zoom = kCompareZoom);

// `window` of `image` enlarged `zoom` times, each pixel a zoom x zoom block (no smoothing, so
// single pixels stay visible).
Image enlarged(const Image& image, const PixelRect& window, int zoom);

// The labelled picture: the three panels (tops aligned, 4-pixel gaps) under their labels, and,
// when `crop` is given, a second row of the three crops enlarged `zoom` times.
Image comparePicture(const Image& expected, const Image& actual, const Image& diff,
                     const std::optional<PixelRect>& crop, int zoom = kCompareZoom);

}  // namespace vf

// The structural similarity index (SSIM) of Wang, Bovik, Sheikh and Simoncelli, "Image quality
// assessment: from error visibility to structural similarity", IEEE Transactions on Image
// Processing 13(4), 2004: a perceptual measure of how alike two images look, 1 for identical
// images, lower as structure (edges, texture), contrast or brightness differ. It complements
// the pixel count of image_diff.h: a body moved by a few pixels changes few pixels but breaks
// local structure; a small brightness shift over the whole frame changes many pixels a little
// and barely lowers SSIM.
#pragma once

#include "render/image.h"
#include "render/output/pixel_mask.h"

namespace vf {

// Mean SSIM of the luma (Rec. 601 weights, 0..255) of two images of the same size, with the
// paper's constants: an 11 x 11 Gaussian window of standard deviation 1.5 pixels (weights
// normalised to sum 1), K1 = 0.01, K2 = 0.03, L = 255, averaged over every window that lies
// wholly inside the image (the reference implementation's "valid" filtering) and whose centre
// is not masked. Masked pixels of `actual` take `expected`'s values, so a mask hides exactly its
// rectangle. An image under 11 pixels on a side is one window with uniform weights. Returns 1
// when no window is left.
double meanSsim(const Image& expected, const Image& actual, const PixelMask& mask = {});

}  // namespace vf

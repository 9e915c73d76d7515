#include "render/output/image_diff.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>

#include "render/output/ssim.h"

namespace vf {

// Why DiffTolerance's defaults are 8/255 and 0.05%. Measured with every scene in scenes/ at
// 320x180 (the golden suite's frames and more, 50 frames; Mesa 22.3.6 llvmpipe, LLVM 15):
// - Rounding noise. OSMesa against EGL, LP_NUM_THREADS=1 or 3 against the default,
//   LP_NATIVE_VECTOR_WIDTH=128 against 256, GALLIVM_PERF sampling shortcuts turned off: all
//   byte-identical. Different code generation, standing in for another CPU
//   (GALLIUM_OVERRIDE_CPU_CAPS=sse4.1 or sse2, GALLIUM_NOSSE=1): at most 19 pixels (0.033%)
//   differ at all, nearly all by 1/255 (the dither rounding the other way), and at most 2
//   pixels (0.0035%) by more than any threshold from 1 to 16 (lone shadow-edge pixels, up to
//   20/255). So noise is a handful of pixels whatever the threshold: the fraction must absorb
//   it, and 0.05% (29 pixels at 320x180) is 14 times the worst case.
// - A moved body. A cube of scenes/cubes.toml moved by one leaf voxel (0.3/16 m at Lv 4) along
//   x, y or z, seen by a fixed camera: 124 to 169 pixels (0.22% to 0.29%) over 8/255, 4 times
//   the limit (with the automatic camera, which then frames the scene differently, 3% to 6%).
// - A changed light (the default sun of render/light.h turned in tests/golden/cubes' frames by
//   golden_frames_test). By 2 degrees (azimuth or elevation): 0.024% to 0.208% per frame,
//   mostly at shadow edges; by 5 degrees: 0.045% to 1.94%, every frame over in azimuth, and in
//   elevation all but the cubes at rest, whose shadows are small. A limit that caught every
//   2-degree frame (0.024%) would sit within 7 times of the noise measured here, too close for
//   other machines and Mesa versions.
// - The threshold: 8/255 is far above the 1/255 dither noise and low enough that a shading
//   change across a whole face counts (the sun 10 degrees higher: 63% to 69% of pixels over
//   8/255).

namespace {

// Largest channel difference of one pixel.
int pixelDiff(const std::uint8_t* a, const std::uint8_t* b) {
  return std::max({std::abs(a[0] - b[0]), std::abs(a[1] - b[1]), std::abs(a[2] - b[2])});
}

// Rec. 709 luma of an sRGB-encoded pixel, 0..255 (good enough for a backdrop).
int luma(const std::uint8_t* p) { return (54 * p[0] + 183 * p[1] + 19 * p[2] + 128) >> 8; }

void put(Image& image, int x, int y, int r, int g, int b) {
  std::uint8_t* p = image.pixel(x, y);
  p[0] = static_cast<std::uint8_t>(std::clamp(r, 0, 255));
  p[1] = static_cast<std::uint8_t>(std::clamp(g, 0, 255));
  p[2] = static_cast<std::uint8_t>(std::clamp(b, 0, 255));
}

std::string percent(double fraction) {
  char buf[32];
  // Enough digits that a fraction just over a 0.05% limit does not print as the limit.
  std::snprintf(buf, sizeof buf, fraction < 0.01 ? "%.3f%%" : "%.2f%%", 100 * fraction);
  return buf;
}

}  // namespace

DiffMetrics compareImages(const Image& expected, const Image& actual, int threshold,
                          const PixelMask& mask) {
  DiffMetrics m;
  m.width = expected.width;
  m.height = expected.height;
  m.threshold = threshold;
  m.pixels = static_cast<std::int64_t>(expected.width) * expected.height;
  if (expected.width != actual.width || expected.height != actual.height) {
    m.sameSize = false;
    m.maxChannelDiff = 255;
    m.differingPixels = m.pixels;
    m.differingFraction = 1;
    return m;
  }
  // Sum of squares in an integer: exact, and the same whatever the order.
  std::uint64_t squares = 0;
  for (int y = 0; y < expected.height; ++y)
    for (int x = 0; x < expected.width; ++x) {
      if (masked(mask, x, y)) {
        ++m.maskedPixels;
        continue;
      }
      const std::uint8_t* e = expected.pixel(x, y);
      const std::uint8_t* a = actual.pixel(x, y);
      for (int c = 0; c < 3; ++c) {
        const int d = e[c] - a[c];
        squares += static_cast<std::uint64_t>(d * d);
      }
      const int d = pixelDiff(e, a);
      m.maxChannelDiff = std::max(m.maxChannelDiff, d);
      if (d > threshold) ++m.differingPixels;
    }
  m.pixels -= m.maskedPixels;
  m.differingFraction = m.pixels > 0 ? static_cast<double>(m.differingPixels) / m.pixels : 0;
  m.ssim = meanSsim(expected, actual, mask);
  const double mse = m.pixels > 0 ? static_cast<double>(squares) / (3.0 * m.pixels) : 0;
  m.psnr = mse > 0 ? 10 * std::log10(255.0 * 255.0 / mse) : std::numeric_limits<double>::infinity();
  return m;
}

bool withinTolerance(const DiffMetrics& metrics, const DiffTolerance& tolerance) {
  return metrics.sameSize && metrics.differingFraction <= tolerance.maxFraction &&
         (!tolerance.minSsim || metrics.ssim >= *tolerance.minSsim);
}

std::string describe(const DiffMetrics& m, const Image& expected, const Image& actual) {
  char buf[200];
  if (!m.sameSize) {
    std::snprintf(buf, sizeof buf, "size differs: expected %dx%d, actual %dx%d", expected.width,
                  expected.height, actual.width, actual.height);
    return buf;
  }
  char psnr[32];
  if (std::isinf(m.psnr)) {
    std::snprintf(psnr, sizeof psnr, "inf");
  } else {
    std::snprintf(psnr, sizeof psnr, "%.1f dB", m.psnr);
  }
  char masked[48] = "";
  if (m.maskedPixels > 0)
    std::snprintf(masked, sizeof masked, ", %lld masked", static_cast<long long>(m.maskedPixels));
  std::snprintf(buf, sizeof buf,
                "max diff %d/255, %s of pixels differ (%lld of %lld > %d/255%s), "
                "PSNR %s, SSIM %.5f",
                m.maxChannelDiff, percent(m.differingFraction).c_str(),
                static_cast<long long>(m.differingPixels), static_cast<long long>(m.pixels),
                m.threshold, masked, psnr, m.ssim);
  return buf;
}

Image diffImage(const Image& expected, const Image& actual, int threshold, const PixelMask& mask) {
  Image out(expected.width, expected.height);
  for (int y = 0; y < out.height; ++y) {
    for (int x = 0; x < out.width; ++x) {
      const std::uint8_t* e = expected.pixel(x, y);
      // Dim grey: enough of the picture to see where a difference is, dark enough for red
      // and blue to stand out.
      const int grey = 24 + luma(e) * 2 / 5;
      if (x >= actual.width || y >= actual.height) {
        put(out, x, y, 255, 0, 0);
        continue;
      }
      if (masked(mask, x, y)) {
        put(out, x, y, grey / 3, grey / 3, grey / 3);
        continue;
      }
      const int d = pixelDiff(e, actual.pixel(x, y));
      if (d > threshold) {
        // 128..255 by magnitude: even a difference just over the threshold is plainly red.
        put(out, x, y, 128 + d / 2, 0, 0);
      } else if (d > 0) {
        put(out, x, y, grey / 2, grey / 2, grey + 64);
      } else {
        put(out, x, y, grey, grey, grey);
      }
    }
  }
  return out;
}

}  // namespace vf

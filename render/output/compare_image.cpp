#include "render/output/compare_image.h"

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstdlib>
#include <string>
#include <vector>

#include "render/output/bitmap_font.h"

namespace vf {
namespace {

constexpr int kGap = 4;
constexpr int kLabelScale = 2;
constexpr int kBand = kGlyphHeight * kLabelScale + 8;  // label band above each row of panels
constexpr std::uint8_t kBackground = 16;
constexpr std::array<std::uint8_t, 3> kLabelColour{230, 230, 230};
constexpr std::array<std::uint8_t, 3> kOutline{255, 210, 0};

int channelDiff(const std::uint8_t* a, const std::uint8_t* b) {
  return std::max({std::abs(a[0] - b[0]), std::abs(a[1] - b[1]), std::abs(a[2] - b[2])});
}

// Summed-area table of the pixels that differ by more than `over` (outside the mask):
// s[(y) * (w + 1) + x] counts those above and left of (x, y).
std::vector<std::int64_t> differingSums(const Image& e, const Image& a, int over,
                                        const PixelMask& mask) {
  const int w = e.width, h = e.height;
  std::vector<std::int64_t> s(static_cast<std::size_t>(w + 1) * (h + 1), 0);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const bool hit = !masked(mask, x, y) && channelDiff(e.pixel(x, y), a.pixel(x, y)) > over;
      s[static_cast<std::size_t>(y + 1) * (w + 1) + x + 1] =
          (hit ? 1 : 0) + s[static_cast<std::size_t>(y) * (w + 1) + x + 1] +
          s[static_cast<std::size_t>(y + 1) * (w + 1) + x] -
          s[static_cast<std::size_t>(y) * (w + 1) + x];
    }
  return s;
}

// The window of ww x wh with the largest count, first in row order; nullopt when all are 0.
std::optional<PixelRect> densestWindow(const std::vector<std::int64_t>& s, int w, int h, int ww,
                                       int wh) {
  const auto at = [&](int x, int y) { return s[static_cast<std::size_t>(y) * (w + 1) + x]; };
  std::int64_t best = 0;
  std::optional<PixelRect> where;
  for (int y = 0; y + wh <= h; ++y)
    for (int x = 0; x + ww <= w; ++x) {
      const std::int64_t n = at(x + ww, y + wh) - at(x, y + wh) - at(x + ww, y) + at(x, y);
      if (n > best) best = n, where = PixelRect{x, y, ww, wh};
    }
  return where;
}

// The window moved to centre the differing pixels it holds (their bounding box fits in it, so
// it keeps them all: still a densest window), within the image.
PixelRect centred(PixelRect r, const Image& e, const Image& a, int over, const PixelMask& mask) {
  int x0 = r.x + r.width, y0 = r.y + r.height, x1 = r.x, y1 = r.y;
  for (int y = r.y; y < r.y + r.height; ++y)
    for (int x = r.x; x < r.x + r.width; ++x)
      if (!masked(mask, x, y) && channelDiff(e.pixel(x, y), a.pixel(x, y)) > over)
        x0 = std::min(x0, x), x1 = std::max(x1, x), y0 = std::min(y0, y), y1 = std::max(y1, y);
  r.x = std::clamp((x0 + x1 + 1) / 2 - r.width / 2, 0, e.width - r.width);
  r.y = std::clamp((y0 + y1 + 1) / 2 - r.height / 2, 0, e.height - r.height);
  return r;
}

void fill(Image& image, std::uint8_t value) {
  std::fill(image.rgb.begin(), image.rgb.end(), value);
}

void paste(Image& out, const Image& part, int left, int top) {
  for (int y = 0; y < part.height; ++y)
    std::copy_n(part.pixel(0, y), static_cast<std::size_t>(part.width) * 3,
                out.pixel(left, top + y));
}

void outline(Image& image, const PixelRect& r, int left, int top) {
  const auto dot = [&](int x, int y) {
    if (x >= 0 && y >= 0 && x < image.width && y < image.height)
      std::copy_n(kOutline.data(), 3, image.pixel(x, y));
  };
  for (int x = r.x - 1; x <= r.x + r.width; ++x)
    dot(left + x, top + r.y - 1), dot(left + x, top + r.y + r.height);
  for (int y = r.y - 1; y <= r.y + r.height; ++y)
    dot(left + r.x - 1, top + y), dot(left + r.x + r.width, top + y);
}

// One row of panels under their labels, starting at `top`.
void panelRow(Image& out, int top, const std::array<const Image*, 3>& panels,
              const std::array<std::string, 3>& labels) {
  int left = 0;
  for (int i = 0; i < 3; ++i) {
    drawText(out, left + 2, top + (kBand - kGlyphHeight * kLabelScale) / 2, labels[i], kLabelScale,
             kLabelColour);
    paste(out, *panels[i], left, top + kBand);
    left += panels[i]->width + kGap;
  }
}

}  // namespace

std::optional<PixelRect> changedRegion(const Image& expected, const Image& actual, int threshold,
                                       const PixelMask& mask, int zoom) {
  if (expected.width != actual.width || expected.height != actual.height) return std::nullopt;
  const int w = expected.width, h = expected.height;
  const int ww = std::min(w, (w + zoom - 1) / zoom), wh = std::min(h, (h + zoom - 1) / zoom);
  for (const int over : {threshold, 0}) {
    const auto sums = differingSums(expected, actual, over, mask);
    if (auto r = densestWindow(sums, w, h, ww, wh))
      return centred(*r, expected, actual, over, mask);
  }
  return std::nullopt;
}

Image enlarged(const Image& image, const PixelRect& window, int zoom) {
  Image out(window.width * zoom, window.height * zoom);
  for (int y = 0; y < out.height; ++y)
    for (int x = 0; x < out.width; ++x)
      std::copy_n(image.pixel(window.x + x / zoom, window.y + y / zoom), 3, out.pixel(x, y));
  return out;
}

Image comparePicture(const Image& expected, const Image& actual, const Image& diff,
                     const std::optional<PixelRect>& crop, int zoom) {
  const std::array<const Image*, 3> full{&expected, &actual, &diff};
  int width = 2 * kGap, rowHeight = 0;
  for (const Image* p : full) width += p->width, rowHeight = std::max(rowHeight, p->height);
  std::array<Image, 3> zoomed;
  int zoomHeight = 0;
  if (crop) {
    for (int i = 0; i < 3; ++i) zoomed[i] = enlarged(*full[i], *crop, zoom);
    zoomHeight = kBand + zoomed[0].height;
    width = std::max(width, 3 * zoomed[0].width + 2 * kGap);
  }
  Image out(width, kBand + rowHeight + (crop ? kGap + zoomHeight : 0));
  fill(out, kBackground);
  panelRow(out, 0, full, {"EXPECTED", "ACTUAL", "DIFF"});
  if (!crop) return out;
  int left = 0;
  for (const Image* p : full) outline(out, *crop, left, kBand), left += p->width + kGap;
  const std::string z = std::string(" ").append(std::to_string(zoom)).append("x");
  panelRow(out, kBand + rowHeight + kGap, {&zoomed[0], &zoomed[1], &zoomed[2]},
           {"EXPECTED" + z, "ACTUAL" + z, "DIFF" + z});
  return out;
}

}  // namespace vf

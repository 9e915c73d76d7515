#include "render/overlay.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <numbers>

#include "render/output/bitmap_font.h"

namespace vf {
namespace {

constexpr double kDegrees = std::numbers::pi / 180;

// Fills the part of `box` inside the image with `colour`, opaque where the image has alpha.
void fill(Image& image, const OverlayBox& box, std::array<std::uint8_t, 3> colour) {
  const int x0 = std::max(box.x0, 0), x1 = std::min(box.x1, image.width);
  const int y0 = std::max(box.y0, 0), y1 = std::min(box.y1, image.height);
  for (int y = y0; y < y1; ++y)
    for (int x = x0; x < x1; ++x) std::memcpy(image.pixel(x, y), colour.data(), 3);
  if (image.alpha.empty()) return;
  for (int y = y0; y < y1; ++y)
    std::fill_n(image.alpha.begin() + static_cast<std::ptrdiff_t>(y) * image.width + x0,
                std::max(x1 - x0, 0), std::uint8_t{255});
}

// Panel padding and distance from the frame's edge, in frame pixels.
int padding(int scale) { return 2 * scale; }
int margin(int scale) { return 4 * scale; }

// The bar, its end ticks and its label on a panel at the bottom left.
void drawScaleBar(Image& image, const ScaleBar& bar, int scale) {
  const int pad = padding(scale), edge = margin(scale);
  const int labelHeight = kGlyphHeight * scale, tick = 4 * scale, gap = 2 * scale;
  const int width = std::max(bar.pixels, textWidth(bar.label, scale));
  OverlayBox panel;
  panel.x0 = edge;
  panel.x1 = edge + width + 2 * pad;
  panel.y1 = image.height - edge;
  panel.y0 = panel.y1 - (labelHeight + gap + tick + 2 * pad);
  fill(image, panel, kOverlayPanel);
  drawText(image, panel.x0 + pad, panel.y0 + pad, bar.label, scale, kOverlayInk);
  const int left = panel.x0 + pad, bottom = panel.y1 - pad;
  // The bar: `scale` pixels thick along the bottom, ticks up at both ends, so its length
  // reads from the outer edges of the ticks.
  fill(image, OverlayBox{left, bottom - scale, left + bar.pixels, bottom}, kOverlayInk);
  fill(image, OverlayBox{left, bottom - tick, left + scale, bottom}, kOverlayInk);
  fill(image, OverlayBox{left + bar.pixels - scale, bottom - tick, left + bar.pixels, bottom},
       kOverlayInk);
}

}  // namespace

int overlayScale(int height) { return std::max(1, height / 240); }

std::string overlayTimeText(double time, double speed) {
  char text[96];
  std::snprintf(text, sizeof text, "t = %.2f s", time);
  std::string out = text;
  if (speed != 1) {
    std::snprintf(text, sizeof text, " (%gx)", speed);
    out += text;
  }
  return out;
}

TextPlacement timeOverlayPlacement(const std::string& text, int /*width*/, int height) {
  const int scale = overlayScale(height), pad = padding(scale), edge = margin(scale);
  TextPlacement p;
  p.panel = OverlayBox{edge, edge, edge + textWidth(text, scale) + 2 * pad,
                       edge + kGlyphHeight * scale + 2 * pad};
  p.textX = edge + pad;
  p.textY = edge + pad;
  return p;
}

ScaleBar chooseScaleBar(double pixelsPerMetre, int maxPixels) {
  ScaleBar bar;
  if (!(std::isfinite(pixelsPerMetre) && pixelsPerMetre > 0) || maxPixels < 1) return bar;
  const double longest = maxPixels / pixelsPerMetre;  // m
  // The largest 1, 2 or 5 times 10^n not above `longest`: start at the decade below it.
  double decade = std::pow(10.0, std::floor(std::log10(longest)));
  for (const double step : {5.0, 2.0, 1.0}) {
    if (step * decade * pixelsPerMetre <= maxPixels) {
      bar.metres = step * decade;
      break;
    }
  }
  if (bar.metres == 0) bar.metres = decade / 2;  // log10 rounded up at an exact power
  bar.pixels = static_cast<int>(std::lround(bar.metres * pixelsPerMetre));
  char text[64];
  if (bar.metres >= 1000) {
    std::snprintf(text, sizeof text, "%g km", bar.metres / 1000);
  } else {
    std::snprintf(text, sizeof text, "%g m", bar.metres);
  }
  bar.label = text;
  return bar;
}

double pixelsPerMetreAtLookAt(const CameraView& camera, int height) {
  const double distance = (camera.lookAt - camera.position).norm();
  return height / (2 * distance * std::tan(camera.fovYDegrees * kDegrees / 2));
}

void drawOverlays(Image& image, const OverlaySettings& settings, const CameraView& camera,
                  double time, double speed) {
  const int scale = overlayScale(image.height);
  if (settings.time) {
    const std::string text = overlayTimeText(time, speed);
    const TextPlacement p = timeOverlayPlacement(text, image.width, image.height);
    fill(image, p.panel, kOverlayPanel);
    drawText(image, p.textX, p.textY, text, scale, kOverlayInk);
  }
  if (settings.scale) {
    // At most a quarter of the frame's width: a bar long enough to read, short enough to leave
    // the picture alone.
    const ScaleBar bar =
        chooseScaleBar(pixelsPerMetreAtLookAt(camera, image.height), image.width / 4);
    if (bar.pixels >= 2 * scale) drawScaleBar(image, bar, scale);
  }
}

}  // namespace vf

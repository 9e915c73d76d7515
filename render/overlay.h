// Overlays drawn onto a finished frame by voxfall itself (no external tool): the simulated
// time and a scale bar, each on an opaque dark panel so it reads over sky, floor and terrain
// alike, in the built-in bitmap font (render/output/bitmap_font.h), so the pixels are the same
// on every machine. The time sits at the top left, the scale bar at the bottom left; the sizes
// grow with the frame's height. Plain pixels, no GL: unit-testable.
#pragma once

#include <array>
#include <cstdint>
#include <string>

#include "render/camera.h"
#include "render/image.h"

namespace vf {

// Which overlays to draw ([output] overlay, `render --overlay`).
struct OverlaySettings {
  bool time = false;   // "t = 1.25 s", and "(0.5x)" when the speed is not 1
  bool scale = false;  // a bar of a round length in metres at the camera's look-at distance
};

// The overlay's colours: text and bar on a dark panel.
inline constexpr std::array<std::uint8_t, 3> kOverlayInk{240, 240, 240};
inline constexpr std::array<std::uint8_t, 3> kOverlayPanel{24, 24, 24};

// Font pixels per overlay pixel for a frame `height` pixels high: 1 up to 479 rows, then one
// more per 240 (3 at 720, 4 at 1080), so the text keeps its share of the frame.
int overlayScale(int height);

// The time text: "t = 12.40 s" (two decimals), with " (0.5x)" appended when speed != 1
// (speed printed with %g).
std::string overlayTimeText(double time, double speed);

// A rectangle of pixels, x in [x0, x1), y in [y0, y1), y = 0 at the top.
struct OverlayBox {
  int x0 = 0, y0 = 0, x1 = 0, y1 = 0;
};
// Where the time overlay goes in a frame of width x height: its panel, and the top-left corner
// of its text (drawn with drawText at overlayScale(height)).
struct TextPlacement {
  OverlayBox panel;
  int textX = 0, textY = 0;
};
TextPlacement timeOverlayPlacement(const std::string& text, int width, int height);

// The scale bar: the largest length of 1, 2 or 5 times a power of ten (m) whose bar is at
// most `maxPixels` long at `pixelsPerMetre`, its length in pixels (rounded) and its label
// ("20 m", "0.5 m", "2 km"). metres = 0 when pixelsPerMetre is not finite and positive.
struct ScaleBar {
  double metres = 0;
  int pixels = 0;
  std::string label;
};
ScaleBar chooseScaleBar(double pixelsPerMetre, int maxPixels);

// Pixels per metre, in a frame `height` pixels high, of a length facing `camera` at its
// look-at distance (the vertical field of view spans 2 d tan(fov / 2) metres there).
double pixelsPerMetreAtLookAt(const CameraView& camera, int height);

// Draws the overlays asked for onto `image`: the time of the frame (s) at `speed`, and the
// scale bar of `camera`. Overlay pixels are opaque where the image has an alpha plane.
void drawOverlays(Image& image, const OverlaySettings& settings, const CameraView& camera,
                  double time, double speed);

}  // namespace vf

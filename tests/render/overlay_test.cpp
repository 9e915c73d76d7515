// Overlays (render/overlay.h): the scale bar's round length against hand-worked cases, the
// pixels per metre at the look-at distance against the pinhole formula, and frames drawn
// in-process with and without the overlays: the overlay's panel changes the picture there and
// nowhere else, and the time text in it is, pixel for pixel, the built-in font's rendering of
// the expected string ("t = 0.50 s" for frame 15 at 30 fps; "t = 0.25 s (0.5x)" at speed 0.5)
// on the panel.
#include "render/overlay.h"

#include <gtest/gtest.h>

#include <cstring>
#include <limits>
#include <string>

#include "render/gl/gl_context.h"
#include "render/gl/shader_program.h"
#include "render/output/bitmap_font.h"
#include "render/scene_playback.h"
#include "render_test_util.h"
#include "sim/scene/scene.h"

namespace vf {
namespace {

TEST(Overlay, ScaleBarIsTheLargestOneTwoOrFiveTimesAPowerOfTenThatFits) {
  // 100 px/m, at most 320 px: 3.2 m fit, so 2 m (200 px).
  ScaleBar bar = chooseScaleBar(100, 320);
  EXPECT_DOUBLE_EQ(bar.metres, 2);
  EXPECT_EQ(bar.pixels, 200);
  EXPECT_EQ(bar.label, "2 m");
  // 0.05 px/m: 6.4 km fit, so 5 km (250 px).
  bar = chooseScaleBar(0.05, 320);
  EXPECT_DOUBLE_EQ(bar.metres, 5000);
  EXPECT_EQ(bar.pixels, 250);
  EXPECT_EQ(bar.label, "5 km");
  // 1000 px/m: 0.32 m fit, so 0.2 m (200 px).
  bar = chooseScaleBar(1000, 320);
  EXPECT_NEAR(bar.metres, 0.2, 1e-15);
  EXPECT_EQ(bar.pixels, 200);
  EXPECT_EQ(bar.label, "0.2 m");
  // Exactly a power of ten fits: 10 m at 32 px/m.
  bar = chooseScaleBar(32, 320);
  EXPECT_DOUBLE_EQ(bar.metres, 10);
  EXPECT_EQ(bar.label, "10 m");
  // No scale to be had.
  EXPECT_EQ(chooseScaleBar(0, 320).metres, 0);
  EXPECT_EQ(chooseScaleBar(std::numeric_limits<double>::infinity(), 320).metres, 0);
}

TEST(Overlay, PixelsPerMetreAtTheLookAtDistanceFollowTheFieldOfView) {
  CameraView camera;
  camera.position = Vec3(0, -10, 0);
  camera.lookAt = Vec3::Zero();
  camera.fovYDegrees = 90;  // the view spans 2 d tan(45) = 20 m at d = 10 m
  EXPECT_NEAR(pixelsPerMetreAtLookAt(camera, 200), 10, 1e-12);
}

TEST(Overlay, TimeTextHasTwoDecimalsAndTheSpeedWhenItIsNotOne) {
  EXPECT_EQ(overlayTimeText(12.4, 1), "t = 12.40 s");
  EXPECT_EQ(overlayTimeText(0.25, 0.5), "t = 0.25 s (0.5x)");
  EXPECT_EQ(overlayTimeText(30, 10), "t = 30.00 s (10x)");
  EXPECT_TRUE(fontCovers(overlayTimeText(123.456, 0.25)));
}

const std::string kCubes = std::string(VOXFALL_SOURCE_DIR) + "/scenes/cubes.toml";

Image drawFrame(SceneSpec spec, int k, bool time, bool scale) {
  spec.output.width = 320;
  spec.output.height = 180;
  spec.output.overlayTime = time;
  spec.output.overlayScale = scale;
  auto context = gl::createContext(gl::Backend::osmesa);
  return renderSceneFrames(spec, {k}, *context, gl::findShaderDir()).images.at(0);
}

// Pixels that differ between two images of one size, and whether all lie inside `box`.
int differing(const Image& a, const Image& b, const OverlayBox& box, bool& inside) {
  int n = 0;
  inside = true;
  for (int y = 0; y < a.height; ++y)
    for (int x = 0; x < a.width; ++x)
      if (std::memcmp(a.pixel(x, y), b.pixel(x, y), 3) != 0) {
        ++n;
        inside = inside && x >= box.x0 && x < box.x1 && y >= box.y0 && y < box.y1;
      }
  return n;
}

// The expected panel: its colour with `text` in the font at the placement's offset.
void expectPanelShows(const Image& frame, const TextPlacement& p, const std::string& text) {
  Image panel(p.panel.x1 - p.panel.x0, p.panel.y1 - p.panel.y0);
  for (int y = 0; y < panel.height; ++y)
    for (int x = 0; x < panel.width; ++x) std::memcpy(panel.pixel(x, y), kOverlayPanel.data(), 3);
  drawText(panel, p.textX - p.panel.x0, p.textY - p.panel.y0, text, overlayScale(frame.height),
           kOverlayInk);
  int wrong = 0;
  for (int y = 0; y < panel.height; ++y)
    for (int x = 0; x < panel.width; ++x)
      wrong += std::memcmp(frame.pixel(p.panel.x0 + x, p.panel.y0 + y), panel.pixel(x, y), 3) != 0;
  EXPECT_EQ(wrong, 0) << "the time panel does not show '" << text << "'";
}

TEST(Overlay, TheTimeIsDrawnInTheFontOnItsPanelAndNowhereElse) {
  const SceneSpec spec = loadScene(kCubes);
  const Image plain = drawFrame(spec, 15, false, false);
  const Image timed = drawFrame(spec, 15, true, false);
  const std::string text = "t = 0.50 s";  // frame 15 at 30 fps
  const TextPlacement p = timeOverlayPlacement(text, 320, 180);
  bool inside = false;
  EXPECT_GT(differing(plain, timed, p.panel, inside), 0);
  EXPECT_TRUE(inside) << "the overlay changed pixels outside its panel";
  expectPanelShows(timed, p, text);

  // At speed 0.5 frame 15 is at 0.25 s, and the text says the speed.
  SceneSpec slow = spec;
  slow.output.speed = 0.5;
  const std::string slowText = "t = 0.25 s (0.5x)";
  expectPanelShows(drawFrame(slow, 15, true, false), timeOverlayPlacement(slowText, 320, 180),
                   slowText);
}

TEST(Overlay, TheScaleBarIsDrawnAtTheBottomLeft) {
  const SceneSpec spec = loadScene(kCubes);
  const Image plain = drawFrame(spec, 0, false, false);
  const Image barred = drawFrame(spec, 0, false, true);
  // The bar's panel stays in the bottom-left quarter (the bar is at most a quarter of the width,
  // its label above it).
  bool inside = false;
  EXPECT_GT(differing(plain, barred, OverlayBox{0, 90, 160, 180}, inside), 0);
  EXPECT_TRUE(inside) << "the scale bar changed pixels outside the bottom-left quarter";
}

}  // namespace
}  // namespace vf

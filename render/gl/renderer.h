// Draws a DrawList off-screen and reads the frame back. One Renderer per context and frame
// size; it keeps the GPU copies of meshes (one per DrawMesh key) between frames.
//
// A frame: shadow map from the sun (orthographic, fitted to the casters; redrawn only where a
// caster changed since the last frame) -> scene into a multisampled
// linear-light HDR target (bodies, floor with grid) -> present (sample average with the sky
// where nothing was drawn, highlight shoulder, sRGB encoding, ordered dither) into 8 bits ->
// read back top row first. Scene and present are scissored to the part of the picture that
// can have changed since the last frame; the rest of both targets is kept.
#pragma once

#include <memory>
#include <string>

#include "render/draw_data.h"
#include "render/image.h"

namespace vf::gl {

class Context;

struct RenderSettings {
  int width = 1280;  // pixels
  int height = 720;
  // Multisample anti-aliasing samples; where the context offers fewer than asked (and more
  // than 1 was asked), 2x2 supersampling is used instead.
  int samples = 4;
  int shadowMapSize = 2048;  // texels per side
  // Ordered (Bayer) dither of +-0.5 of an 8-bit step before quantising, against banding in the
  // sky gradient and soft shadows. Deterministic: a fixed pattern of the pixel position.
  bool dither = true;
  // Redraw only the part of the frame that can differ from the last one drawn (bodies that
  // moved and their shadows; render/redraw_region.h says why the result is exact). false:
  // draw every frame whole.
  bool incremental = true;
  // Skip work that provably changes no pixel: shadow lookups on the floor where no caster's
  // shadow can reach it (RedrawTracker::floorShadows), and the sky where the floor covers
  // every sample (floorCovers). false: do it everywhere (the same bytes; for tests).
  bool skipHiddenWork = true;
  // A transparent background for compositing: the sky and the floor have alpha 0, except the
  // floor's shadows, kept as black at the opacity that darkens what lies behind as much as the
  // shadow darkens the floor (a shadow catcher); bodies and terrain are opaque, and
  // anti-aliased edges partly so. The frame then has an alpha plane (Image::alpha).
  bool alpha = false;
  // Wait for the GL after each pass and add its time to Renderer::passTimes() (benchmarks:
  // the waits cost llvmpipe some overlap between passes, so frames draw a little slower).
  bool timePasses = false;
  std::string shaderDir;  // the GLSL folder; "": findShaderDir()'s default
};

// Wall time of each part of the frames drawn since the renderer was made, with
// RenderSettings::timePasses, s.
struct PassTimes {
  double shadow = 0;    // the shadow map
  double scene = 0;     // clearing the scene target and drawing bodies, terrain and trails
  double floor = 0;     // the floor
  double present = 0;   // samples averaged, sky, shoulder, sRGB, dither
  double readback = 0;  // glReadPixels and the copy into the Image
  double total() const { return shadow + scene + floor + present + readback; }
};

class Renderer {
 public:
  // Compiles the shaders and makes the framebuffers. The context must be current and outlive
  // the renderer. Throws InputError for shader problems, GlError for GL ones.
  Renderer(Context& context, const RenderSettings& settings);
  ~Renderer();
  Renderer(const Renderer&) = delete;
  Renderer& operator=(const Renderer&) = delete;

  // Draws one frame into `out` (resized to width x height): RGB8, sRGB, top row first, with
  // an alpha plane when RenderSettings::alpha is set (none otherwise).
  void render(const DrawList& list, Image& out);
  Image render(const DrawList& list);

  // "4x MSAA" or "2x2 supersampling": what anti-aliasing the context allowed.
  std::string antialiasing() const;
  // The share of the last frame's pixels that were drawn (1: the whole frame; 0: none, since
  // nothing changed).
  double redrawnFraction() const;
  // Shares of the last frame's pixels whose floor was shaded without shadow lookups, and that
  // were presented without working out the sky (RenderSettings::skipHiddenWork).
  double unshadowedFloorFraction() const;
  double skyFreeFraction() const;
  // All zero unless RenderSettings::timePasses.
  const PassTimes& passTimes() const;
  const RenderSettings& settings() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace vf::gl

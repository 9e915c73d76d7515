#include "render/gl/renderer.h"

#include <algorithm>
#include <chrono>
#include <string>
#include <utility>

#include "render/gl/renderer_impl.h"
#include "render/gl/shader_program.h"
#include "sim/scene/scene.h"

namespace vf::gl {

Renderer::Renderer(Context& context, const RenderSettings& settings)
    : impl_(std::make_unique<Impl>(context, settings)) {
  for (const auto& [side, pixels] :
       {std::pair<const char*, int>{"width", settings.width}, {"height", settings.height}}) {
    const std::string problem = frameSideProblem(side, pixels);
    if (!problem.empty()) throw GlError(problem);
  }
  Impl& r = *impl_;
  const std::string dir = findShaderDir(settings.shaderDir);
  // The VF_ALPHA variants of the floor and present programs for a transparent background.
  auto defines = [&](std::vector<std::string> names) {
    if (settings.alpha) names.push_back("VF_ALPHA");
    return names;
  };
  r.sceneProgram = std::make_unique<ShaderProgram>(r.gl, dir, "scene.vert", "scene.frag");
  r.drapedSceneProgram = std::make_unique<ShaderProgram>(r.gl, dir, "scene.vert", "scene.frag",
                                                         std::vector<std::string>{"VF_DRAPED"});
  r.groundProgram =
      std::make_unique<ShaderProgram>(r.gl, dir, "ground.vert", "ground.frag", defines({}));
  r.litGroundProgram = std::make_unique<ShaderProgram>(r.gl, dir, "ground.vert", "ground.frag",
                                                       defines({"VF_UNSHADOWED"}));
  r.shadowProgram = std::make_unique<ShaderProgram>(r.gl, dir, "shadow.vert", "shadow.frag");
  r.presentProgram =
      std::make_unique<ShaderProgram>(r.gl, dir, "fullscreen.vert", "present.frag", defines({}));
  if (!settings.alpha) {
    r.floorPresentProgram = std::make_unique<ShaderProgram>(
        r.gl, dir, "fullscreen.vert", "present.frag", std::vector<std::string>{"VF_NO_SKY"});
  }
  r.createTargets();
  const GLenum error = r.gl.GetError();
  if (error != GL_NO_ERROR) {
    throw GlError("OpenGL error " + std::to_string(error) + " while setting up the renderer");
  }
}

Renderer::~Renderer() = default;

void Renderer::Impl::copyReadback(Image& out) const {
  const int w = settings.width, h = settings.height;
  // GL's rows run bottom to top; images run top to bottom.
  if (out.width != w || out.height != h) out = Image(w, h);
  out.alpha.resize(settings.alpha ? static_cast<std::size_t>(w) * h : 0);
  for (int y = 0; y < h; ++y) {
    const std::uint8_t* src = readback.data() + static_cast<std::size_t>(h - 1 - y) * w * 4;
    std::uint8_t* dst = out.pixel(0, y);
    for (int x = 0; x < w; ++x) {
      dst[3 * x + 0] = src[4 * x + 0];
      dst[3 * x + 1] = src[4 * x + 1];
      dst[3 * x + 2] = src[4 * x + 2];
    }
    if (settings.alpha) {
      std::uint8_t* a = out.alpha.data() + static_cast<std::size_t>(y) * w;
      for (int x = 0; x < w; ++x) a[x] = src[4 * x + 3];
    }
  }
}

void Renderer::render(const DrawList& list, Image& out) {
  Impl& r = *impl_;
  const Api& gl = r.gl;
  const ShadowProjection shadow =
      fitShadowProjection(list.sunDirection, list.casterCentre, list.casterRadius,
                          list.groundHeight.value_or(list.casterCentre.z() - list.casterRadius),
                          r.settings.shadowMapSize);
  // Every frame updates the tracker; only an unbroken run of whole frames may use its answer.
  // The reach of a shadow lookup from its surface point, in shadow-map texels (common.glsl):
  // the normal offset (at most 4), the filter's farthest tap (0.95 sqrt 2 < 1.35), the
  // bilinear footprint (1), and a texel for rounding.
  std::optional<std::vector<PixelRect>> regions =
      r.tracker.update(list, shadow, 7.35 * shadow.texelSize);
  const bool valid = r.targetsValid;
  r.targetsValid = false;
  const int w = r.settings.width, h = r.settings.height;
  const double pixels = static_cast<double>(w) * h;
  double area = 0;
  if (regions) {
    for (const PixelRect& rect : *regions) area += static_cast<double>(rect.area());
  }
  // Most of the picture: one whole pass costs less than several partial ones.
  if (!r.settings.incremental || !valid || area > 0.7 * pixels) regions.reset();
  r.redrawn = regions ? area / pixels : 1.0;
  r.unshadowedFloor = r.skyFree = 0;

  r.frameMeshes.clear();  // last frame's trails
  if (r.settings.timePasses) {
    gl.Finish();
    r.lapStart = std::chrono::steady_clock::now();
  }
  r.shadowPass(list, shadow, regions ? &r.tracker.shadowMapRegion() : nullptr);
  r.lap(&PassTimes::shadow);
  r.readback.resize(static_cast<std::size_t>(w) * h * 4);
  // Draw the regions (none: all), then read back the rows they span; the other rows keep the
  // last frame's.
  int y0 = h, y1 = 0;
  auto draw = [&](const std::optional<PixelRect>& region) {
    r.scenePass(list, shadow, region);
    r.scissor(region, 1);  // output pixels (the scene's are `supersample` times as many)
    r.presentPass(list, region);
    y0 = std::min(y0, region ? region->y0 : 0);
    y1 = std::max(y1, region ? region->y1 : h);
  };
  if (!regions) {
    draw(std::nullopt);
  } else {
    for (const PixelRect& rect : *regions) draw(rect);
  }
  r.scissor(std::nullopt, 1);
  if (y0 < y1) {
    gl.BindFramebuffer(GL_READ_FRAMEBUFFER, r.presentFbo);
    gl.ReadBuffer(GL_COLOR_ATTACHMENT0);
    gl.PixelStorei(GL_PACK_ALIGNMENT, 4);
    gl.ReadPixels(0, y0, w, y1 - y0, GL_RGBA, GL_UNSIGNED_BYTE,
                  r.readback.data() + static_cast<std::size_t>(y0) * w * 4);
  }
  const GLenum error = gl.GetError();
  if (error != GL_NO_ERROR) {
    throw GlError("OpenGL error " + std::to_string(error) + " while rendering a frame");
  }
  r.targetsValid = true;
  r.copyReadback(out);
  r.lap(&PassTimes::readback);
}

Image Renderer::render(const DrawList& list) {
  Image image;
  render(list, image);
  return image;
}

std::string Renderer::antialiasing() const {
  if (impl_->samples > 1) return std::to_string(impl_->samples) + "x MSAA";
  if (impl_->supersample > 1) return "2x2 supersampling";
  return "none";
}

const RenderSettings& Renderer::settings() const { return impl_->settings; }

const PassTimes& Renderer::passTimes() const { return impl_->passTimes; }

double Renderer::redrawnFraction() const { return impl_->redrawn; }

double Renderer::unshadowedFloorFraction() const {
  return static_cast<double>(impl_->unshadowedFloor) /
         (static_cast<double>(impl_->settings.width) * impl_->settings.height);
}

double Renderer::skyFreeFraction() const {
  return static_cast<double>(impl_->skyFree) /
         (static_cast<double>(impl_->settings.width) * impl_->settings.height);
}

}  // namespace vf::gl

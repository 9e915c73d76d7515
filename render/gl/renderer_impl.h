// The renderer's state between frames (Renderer::Impl), shared by the files that make up the
// renderer: renderer.cpp (a frame from start to read-back), render_targets.cpp (framebuffers,
// GPU meshes, the drape texture) and render_passes.cpp (the shadow, scene and present passes).
// Private to render/gl/: it includes gl_api.h, and with it GL's own header.
#pragma once

#include <chrono>
#include <cstdint>
#include <memory>
#include <optional>
#include <unordered_map>
#include <vector>

#include "render/draw_data.h"
#include "render/gl/gl_api.h"
#include "render/gl/gl_context.h"
#include "render/gl/gpu_mesh.h"
#include "render/gl/renderer.h"
#include "render/gl/shader_program.h"
#include "render/redraw_region.h"

namespace vf::gl {

struct Renderer::Impl {
  Context& context;
  const Api& gl;
  RenderSettings settings;
  int samples = 1;      // MSAA samples of the scene target
  int supersample = 1;  // scene target is this many times the frame size per axis
  int sceneWidth = 0, sceneHeight = 0;

  std::unique_ptr<ShaderProgram> sceneProgram, groundProgram, shadowProgram, presentProgram;
  // Terrain with a picture draped on it: a program of its own, since llvmpipe pays for a
  // texture lookup behind a runtime test on every terrain fragment (4% of a cliff frame).
  std::unique_ptr<ShaderProgram> drapedSceneProgram;
  std::unique_ptr<ShaderProgram> litGroundProgram;     // the floor without shadow lookups
  std::unique_ptr<ShaderProgram> floorPresentProgram;  // present where no sample shows sky
  // With RenderSettings::alpha these are the VF_ALPHA variants: the floor writes its shadow's
  // opacity instead of its colour, and present writes coverage into alpha (no sky, and no
  // floorPresentProgram: the floor is no longer opaque).
  unsigned emptyVao = 0;  // core profile needs a bound VAO even for attribute-less draws
  unsigned shadowFbo = 0, shadowTexture = 0;
  // What the shadow map holds: the light's matrix and every caster (mesh, model matrix). A
  // frame with the same ones reuses it (bodies at rest, a still terrain).
  struct Caster {
    const void* mesh;
    Eigen::Matrix4f model;  // as drawn (single precision)
    bool operator==(const Caster& o) const { return mesh == o.mesh && model == o.model; }
  };
  bool shadowValid = false;
  Mat4 shadowViewProjection = Mat4::Zero();
  std::vector<Caster> shadowCasters;
  // Scene colour: a multisample texture (MSAA) or a plain one (supersampling), read directly
  // by the present pass, so there is no resolve blit.
  unsigned sceneFbo = 0, sceneColor = 0, sceneDepth = 0;
  unsigned presentFbo = 0, presentColor = 0;

  // The drape's texture (sRGB with coverage, mipmapped), made for one DrapeImage and kept
  // while draw lists bring the same one.
  std::shared_ptr<const DrapeImage> drape;
  unsigned drapeTexture = 0;

  struct MeshEntry {
    std::shared_ptr<const TriMesh> pin;  // keeps the key's owner alive: keys are never reused
    std::unique_ptr<GpuMesh> mesh;
  };
  std::unordered_map<const void*, MeshEntry> meshes;  // lookup only, never iterated
  std::vector<std::unique_ptr<GpuMesh>> frameMeshes;  // transient ones, for the current frame
  std::vector<std::uint8_t> readback;

  // Incremental frames: what changed since the last frame, and whether the targets (scene,
  // output, read-back copy) hold that frame whole. A frame that failed part way leaves them
  // invalid, and the next one is drawn whole.
  RedrawTracker tracker;
  bool targetsValid = false;
  double redrawn = 1;
  // Of the last frame: pixels whose floor was shaded without shadow lookups, and pixels
  // presented without working out the sky (skipHiddenWork).
  long long unshadowedFloor = 0, skyFree = 0;
  // RenderSettings::timePasses: what each part took, and when the last timed part ended.
  PassTimes passTimes;
  std::chrono::steady_clock::time_point lapStart;

  Impl(Context& c, const RenderSettings& s)
      : context(c), gl(c.api()), settings(s), tracker(s.width, s.height, s.shadowMapSize) {}
  ~Impl();
  void createTargets();
  const GpuMesh& mesh(const DrawMesh& m);
  // Binds the list's drape to texture unit 1, uploading it when it is new.
  void bindDrape(const DrawList& list);
  // `texels`: the parts of the map to redraw (the rest holds the last frame's casters, which
  // is exact: see RedrawTracker::shadowMapRegion); null: decide by comparing all casters.
  void shadowPass(const DrawList& list, const ShadowProjection& shadow,
                  const std::vector<PixelRect>* texels);
  // `region`: the output pixels to redraw; none for all.
  void scenePass(const DrawList& list, const ShadowProjection& shadow,
                 const std::optional<PixelRect>& region);
  // `region`: as scenePass's (the scissor is set by the caller).
  void presentPass(const DrawList& list, const std::optional<PixelRect>& region);
  void scissor(const std::optional<PixelRect>& region, int scale);
  // One frame's values of the uniforms in common.glsl (scenePass), the same in every program
  // that includes it.
  struct SceneFrame {
    const DrawList& list;
    const ShadowProjection& shadow;
    Mat4 viewProjection;
    Vec3 sun;   // unit, towards the sun
    Vec3 fill;  // unit, towards the fill light
  };
  void useCommon(ShaderProgram& program, const SceneFrame& frame);
  // scenePass's parts: bodies, terrain and trails; then the floor.
  void drawInstances(const SceneFrame& frame, const std::optional<PixelRect>& region);
  void drawFloor(const SceneFrame& frame, const std::optional<PixelRect>& region);
  // The read-back copy (RGBA, bottom row first) into `out`: RGB top row first, and the alpha
  // plane with RenderSettings::alpha.
  void copyReadback(Image& out) const;
  // With timePasses: waits for the GL and adds the time since the last lap to `slot`.
  void lap(double PassTimes::*slot);
  PixelRect wholeFrame() const { return PixelRect{0, 0, settings.width, settings.height}; }
};

}  // namespace vf::gl

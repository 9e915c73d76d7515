#include "render/gl/renderer.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numbers>
#include <unordered_map>
#include <utility>

#include "render/gl/gl_api.h"
#include "render/gl/gl_context.h"
#include "render/gl/gpu_mesh.h"
#include "render/gl/shader_program.h"
#include "render/redraw_region.h"
#include "sim/scene/scene.h"
#include "sim/shape/drape_import.h"

namespace vf::gl {
namespace {

void setMatrix(const Api& gl, int location, const Mat4& m) {
  const Eigen::Matrix4f f = m.cast<float>();  // column-major, as GL expects
  gl.UniformMatrix4fv(location, 1, GL_FALSE, f.data());
}

void setMatrix(const Api& gl, int location, const Eigen::Matrix4f& m) {
  gl.UniformMatrix4fv(location, 1, GL_FALSE, m.data());
}

void setMatrix3(const Api& gl, int location, const Eigen::Matrix3f& m) {
  gl.UniformMatrix3fv(location, 1, GL_FALSE, m.data());
}

void setVec3(const Api& gl, int location, const Vec3& v) {
  gl.Uniform3f(location, static_cast<float>(v.x()), static_cast<float>(v.y()),
               static_cast<float>(v.z()));
}

void checkFramebuffer(const Api& gl, const char* what) {
  const GLenum status = gl.CheckFramebufferStatus(GL_FRAMEBUFFER);
  if (status != GL_FRAMEBUFFER_COMPLETE) {
    char code[16];
    std::snprintf(code, sizeof code, "0x%04X", status);
    throw GlError(std::string("could not make the ") + what + " framebuffer (status " + code + ")");
  }
}

// Fill light: opposite the sun's azimuth, 25 degrees high, no shadow. It keeps the faces
// turned from the sun from going flat grey, so their facets still read.
Vec3 fillDirection(const Vec3& sun) {
  Vec3 horizontal(-sun.x(), -sun.y(), 0);
  if (horizontal.norm() < 1e-6) horizontal = Vec3(1, 0, 0);
  horizontal.normalize();
  const double elevation = 25 * std::numbers::pi / 180;
  return (horizontal * std::cos(elevation) + Vec3::UnitZ() * std::sin(elevation)).normalized();
}

// Half the side of the floor square drawn around the camera: past the fade distance, where
// the floor has faded into the sky colour, which present.frag continues seamlessly.
double groundHalfSide(const DrawList& list) { return list.groundFadeEnd * 1.02; }

}  // namespace

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
  // With timePasses: waits for the GL and adds the time since the last lap to `slot`.
  void lap(double PassTimes::*slot);
  PixelRect wholeFrame() const { return PixelRect{0, 0, settings.width, settings.height}; }
};

Renderer::Impl::~Impl() {
  meshes.clear();
  frameMeshes.clear();
  gl.DeleteFramebuffers(1, &shadowFbo);
  gl.DeleteTextures(1, &shadowTexture);
  gl.DeleteFramebuffers(1, &sceneFbo);
  gl.DeleteTextures(1, &sceneColor);
  gl.DeleteRenderbuffers(1, &sceneDepth);
  gl.DeleteFramebuffers(1, &presentFbo);
  gl.DeleteRenderbuffers(1, &presentColor);
  gl.DeleteVertexArrays(1, &emptyVao);
  if (drapeTexture) gl.DeleteTextures(1, &drapeTexture);
}

void Renderer::Impl::createTargets() {
  GLint maxSamples = 0;
  gl.GetIntegerv(GL_MAX_SAMPLES, &maxSamples);
  if (settings.samples > 1 && maxSamples >= settings.samples) {
    samples = settings.samples;
  } else if (settings.samples > 1) {
    supersample = 2;  // no multisampling to be had: render 4x the pixels and average
  }
  sceneWidth = settings.width * supersample;
  sceneHeight = settings.height * supersample;

  // Shadow map: 32-bit float depth, compared in the sampler (hardware 2x2 PCF with linear
  // filtering); outside the map counts as lit.
  gl.GenTextures(1, &shadowTexture);
  gl.BindTexture(GL_TEXTURE_2D, shadowTexture);
  gl.TexImage2D(GL_TEXTURE_2D, 0, GL_DEPTH_COMPONENT32F, settings.shadowMapSize,
                settings.shadowMapSize, 0, GL_DEPTH_COMPONENT, GL_FLOAT, nullptr);
  gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
  gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_BORDER);
  gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_BORDER);
  const float border[4] = {1, 1, 1, 1};
  gl.TexParameterfv(GL_TEXTURE_2D, GL_TEXTURE_BORDER_COLOR, border);
  gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_COMPARE_MODE, GL_COMPARE_REF_TO_TEXTURE);
  gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_COMPARE_FUNC, GL_LEQUAL);
  gl.GenFramebuffers(1, &shadowFbo);
  gl.BindFramebuffer(GL_FRAMEBUFFER, shadowFbo);
  gl.FramebufferTexture2D(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_TEXTURE_2D, shadowTexture, 0);
  gl.DrawBuffer(GL_NONE);
  gl.ReadBuffer(GL_NONE);
  checkFramebuffer(gl, "shadow-map");

  // Scene: linear light in half floats (no banding in dark shadows before encoding), 32-bit
  // float depth (bodies resting on the floor do not z-fight with it). Alpha 0 marks samples
  // no geometry covered: present.frag puts the sky there.
  gl.GenTextures(1, &sceneColor);
  if (samples > 1) {
    gl.BindTexture(GL_TEXTURE_2D_MULTISAMPLE, sceneColor);
    gl.TexImage2DMultisample(GL_TEXTURE_2D_MULTISAMPLE, samples, GL_RGBA16F, sceneWidth,
                             sceneHeight, GL_TRUE);
  } else {
    gl.BindTexture(GL_TEXTURE_2D, sceneColor);
    gl.TexImage2D(GL_TEXTURE_2D, 0, GL_RGBA16F, sceneWidth, sceneHeight, 0, GL_RGBA, GL_FLOAT,
                  nullptr);
    gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  }
  gl.GenRenderbuffers(1, &sceneDepth);
  gl.BindRenderbuffer(GL_RENDERBUFFER, sceneDepth);
  gl.RenderbufferStorageMultisample(GL_RENDERBUFFER, samples > 1 ? samples : 0,
                                    GL_DEPTH_COMPONENT32F, sceneWidth, sceneHeight);
  gl.GenFramebuffers(1, &sceneFbo);
  gl.BindFramebuffer(GL_FRAMEBUFFER, sceneFbo);
  gl.FramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0,
                          samples > 1 ? GL_TEXTURE_2D_MULTISAMPLE : GL_TEXTURE_2D, sceneColor, 0);
  gl.FramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, sceneDepth);
  checkFramebuffer(gl, "scene");

  // Output: 8-bit sRGB-encoded values (the encoding is done in present.frag).
  gl.GenRenderbuffers(1, &presentColor);
  gl.BindRenderbuffer(GL_RENDERBUFFER, presentColor);
  gl.RenderbufferStorageMultisample(GL_RENDERBUFFER, 0, GL_RGBA8, settings.width, settings.height);
  gl.GenFramebuffers(1, &presentFbo);
  gl.BindFramebuffer(GL_FRAMEBUFFER, presentFbo);
  gl.FramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, presentColor);
  checkFramebuffer(gl, "output");

  gl.BindFramebuffer(GL_FRAMEBUFFER, 0);
  gl.GenVertexArrays(1, &emptyVao);
}

const GpuMesh& Renderer::Impl::mesh(const DrawMesh& m) {
  if (m.transient) {
    frameMeshes.push_back(std::make_unique<GpuMesh>(gl, *m.mesh, m.normals.get()));
    return *frameMeshes.back();
  }
  auto it = meshes.find(m.key);
  if (it == meshes.end()) {
    MeshEntry entry{m.mesh, std::make_unique<GpuMesh>(gl, *m.mesh, m.normals.get())};
    it = meshes.emplace(m.key, std::move(entry)).first;
  }
  return *it->second.mesh;
}

void Renderer::Impl::bindDrape(const DrawList& list) {
  gl.ActiveTexture(GL_TEXTURE1);
  if (list.drape && list.drape != drape) {
    if (!drapeTexture) gl.GenTextures(1, &drapeTexture);
    gl.BindTexture(GL_TEXTURE_2D, drapeTexture);
    gl.PixelStorei(GL_UNPACK_ALIGNMENT, 1);
    // sRGB: the sampler returns linear albedo, filtered in linear light.
    gl.TexImage2D(GL_TEXTURE_2D, 0, GL_SRGB8_ALPHA8, list.drape->width, list.drape->height, 0,
                  GL_RGBA, GL_UNSIGNED_BYTE, list.drape->rgba.data());
    gl.GenerateMipmap(GL_TEXTURE_2D);
    // Closer than a texel to a pixel, each texel is drawn as the square it is (as GIS viewers
    // show rasters): no detail is made up between them, and the picture's cells stay where the
    // data put them. Further away, mipmaps average them.
    gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
    gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    drape = list.drape;
  }
  gl.BindTexture(GL_TEXTURE_2D, list.drape ? drapeTexture : 0);
  gl.ActiveTexture(GL_TEXTURE0);
}

void Renderer::Impl::shadowPass(const DrawList& list, const ShadowProjection& shadow,
                                const std::vector<PixelRect>* texels) {
  std::vector<Caster> casters;
  for (const DrawInstance& inst : list.instances) {
    if (!inst.castsShadow || inst.surface == Surface::unlit) continue;
    casters.push_back(
        Caster{list.meshes[static_cast<std::size_t>(inst.mesh)].key, inst.model.cast<float>()});
  }
  const bool same = shadowValid && shadow.viewProjection == shadowViewProjection;
  if (same && (casters == shadowCasters || (texels && texels->empty()))) {
    shadowCasters = std::move(casters);
    return;  // the map already holds exactly this
  }
  // Redrawn whole, or only where casters changed (the same projection, and the last frame's
  // casters in the rest of the map).
  std::vector<std::optional<PixelRect>> parts;
  if (same && texels) {
    parts.assign(texels->begin(), texels->end());
  } else {
    parts.emplace_back(std::nullopt);
  }
  shadowValid = false;  // until drawn
  gl.BindFramebuffer(GL_FRAMEBUFFER, shadowFbo);
  gl.Viewport(0, 0, settings.shadowMapSize, settings.shadowMapSize);
  gl.ClearDepth(1.0);
  gl.Enable(GL_DEPTH_TEST);
  gl.DepthFunc(GL_LESS);
  gl.DepthMask(GL_TRUE);
  shadowProgram->use();
  setMatrix(gl, shadowProgram->uniform("uLightViewProjection"), shadow.viewProjection);
  for (const std::optional<PixelRect>& part : parts) {
    scissor(part, 1);
    gl.Clear(GL_DEPTH_BUFFER_BIT);
    for (std::size_t i = 0; i < list.instances.size(); ++i) {
      const DrawInstance& inst = list.instances[i];
      if (!inst.castsShadow || inst.surface == Surface::unlit) continue;
      if (part && !tracker.mayCast(i, *part)) continue;  // wholly outside the scissor
      setMatrix(gl, shadowProgram->uniform("uModel"), inst.model);
      mesh(list.meshes[static_cast<std::size_t>(inst.mesh)]).draw();
    }
  }
  scissor(std::nullopt, 1);
  shadowValid = true;
  shadowViewProjection = shadow.viewProjection;
  shadowCasters = std::move(casters);
}

void Renderer::Impl::lap(double PassTimes::*slot) {
  if (!settings.timePasses) return;
  gl.Finish();
  const auto now = std::chrono::steady_clock::now();
  passTimes.*slot += std::chrono::duration<double>(now - lapStart).count();
  lapStart = now;
}

// Restricts drawing and clearing to `region` (output pixels) times `scale` scene pixels each;
// none: everything.
void Renderer::Impl::scissor(const std::optional<PixelRect>& region, int scale) {
  if (!region) {
    gl.Disable(GL_SCISSOR_TEST);
    return;
  }
  gl.Enable(GL_SCISSOR_TEST);
  gl.Scissor(region->x0 * scale, region->y0 * scale, (region->x1 - region->x0) * scale,
             (region->y1 - region->y0) * scale);
}

void Renderer::Impl::scenePass(const DrawList& list, const ShadowProjection& shadow,
                               const std::optional<PixelRect>& region) {
  const double aspect = static_cast<double>(settings.width) / settings.height;
  const Mat4 view = list.camera.viewMatrix();
  const Mat4 projection = list.camera.projectionMatrix(aspect);
  const Mat4 viewProjection = projection * view;
  const Vec3 sun = list.sunDirection.normalized();
  const Vec3 fill = fillDirection(sun);

  gl.BindFramebuffer(GL_FRAMEBUFFER, sceneFbo);
  gl.Viewport(0, 0, sceneWidth, sceneHeight);
  scissor(region, supersample);
  gl.ClearColor(0, 0, 0, 0);
  gl.ClearDepth(1.0);
  gl.Clear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  gl.Enable(GL_DEPTH_TEST);
  gl.DepthFunc(GL_LESS);
  gl.DepthMask(GL_TRUE);
  gl.ActiveTexture(GL_TEXTURE0);
  gl.BindTexture(GL_TEXTURE_2D, shadowTexture);

  // Uniforms of common.glsl, the same in every program that includes it.
  auto setCommon = [&](ShaderProgram& p) {
    p.use();
    setMatrix(gl, p.uniform("uViewProjection"), viewProjection);
    setVec3(gl, p.uniform("uCameraPos"), list.camera.position);
    setVec3(gl, p.uniform("uSunDir"), sun);
    setVec3(gl, p.uniform("uFillDir"), fill);
    setVec3(gl, p.uniform("uSunLight"), list.light.sun);
    setVec3(gl, p.uniform("uSkyLight"), list.light.sky);
    setVec3(gl, p.uniform("uAmbientLight"), list.light.ambient);
    gl.Uniform1f(p.uniform("uFadeStart"), static_cast<float>(list.groundFadeStart));
    gl.Uniform1f(p.uniform("uFadeEnd"), static_cast<float>(list.groundFadeEnd));
    gl.Uniform1i(p.uniform("uShadowMap"), 0);
    setMatrix(gl, p.uniform("uLightViewProjection"), shadow.viewProjection);
    gl.Uniform1f(p.uniform("uShadowTexel"), static_cast<float>(shadow.texelSize));
    // Half a texel of constant depth bias; the normal offset in common.glsl does the rest.
    gl.Uniform1f(p.uniform("uShadowBias"),
                 static_cast<float>(0.5 * shadow.texelSize / shadow.depthRange));
    gl.Uniform1f(p.uniform("uShadowFilter"),
                 0.95f / static_cast<float>(settings.shadowMapSize));  // common.glsl
  };

  // Bodies and terrain first: the floor and the sky then only shade what is still visible.
  if (list.drape) {
    bindDrape(list);
    setCommon(*drapedSceneProgram);
    const DrapeImage& d = *list.drape;
    gl.Uniform1i(drapedSceneProgram->uniform("uDrape"), 1);
    gl.Uniform4f(drapedSceneProgram->uniform("uDrapeRect"), static_cast<float>(d.x0),
                 static_cast<float>(d.y0), static_cast<float>(d.x1 - d.x0),
                 static_cast<float>(d.y1 - d.y0));
  }
  setCommon(*sceneProgram);
  ShaderProgram* current = sceneProgram.get();
  bool culling = false;
  for (std::size_t i = 0; i < list.instances.size(); ++i) {
    const DrawInstance& inst = list.instances[i];
    // Wholly outside the scissor, or, drawing the whole frame, out of view.
    if (region ? !tracker.mayCover(i, *region) : !tracker.maySee(i)) continue;
    ShaderProgram* program = list.drape && inst.surface == Surface::terrain
                                 ? drapedSceneProgram.get()
                                 : sceneProgram.get();
    if (program != current) {
      program->use();
      current = program;
    }
    const GpuTransform transform = gpuTransform(inst.model);
    setMatrix(gl, program->uniform("uModel"), transform.model);
    setMatrix3(gl, program->uniform("uNormalMatrix"), transform.normal);
    gl.Uniform3f(program->uniform("uColor"), inst.color[0], inst.color[1], inst.color[2]);
    gl.Uniform1i(program->uniform("uSurface"), static_cast<int>(inst.surface));
    const DrawMesh& drawn = list.meshes[static_cast<std::size_t>(inst.mesh)];
    if (drawn.closed != culling) {
      culling = drawn.closed;
      if (culling) {
        gl.Enable(GL_CULL_FACE);
        gl.CullFace(GL_BACK);  // counter-clockwise in front: outward triangles seen from outside
      } else {
        gl.Disable(GL_CULL_FACE);
      }
    }
    mesh(drawn).draw();
  }
  gl.Disable(GL_CULL_FACE);
  lap(&PassTimes::scene);

  gl.BindVertexArray(emptyVao);
  if (list.groundHeight) {
    const double half = groundHalfSide(list);
    const Eigen::Vector2d c = list.camera.position.head<2>();
    auto useGround = [&](ShaderProgram& p) {
      setCommon(p);
      gl.Uniform1f(p.uniform("uGroundHeight"), static_cast<float>(*list.groundHeight));
      gl.Uniform2f(p.uniform("uGroundMin"), static_cast<float>(c.x() - half),
                   static_cast<float>(c.y() - half));
      gl.Uniform2f(p.uniform("uGroundMax"), static_cast<float>(c.x() + half),
                   static_cast<float>(c.y() + half));
    };
    // Pushed back a little in depth: where a terrain lies exactly at the floor's level (a
    // valley floor), the terrain wins instead of the two z-fighting in stripes.
    gl.Enable(GL_POLYGON_OFFSET_FILL);
    gl.PolygonOffset(kFloorOffsetFactor, kFloorOffsetUnits);
    const std::optional<std::vector<PixelRect>>& shadows = tracker.floorShadows();
    if (settings.skipHiddenWork && shadows) {
      // Where no shadow can fall, the program without lookups (shadow lookups were a third of
      // a crosses frame's time on llvmpipe). The scissor does not change the grid's
      // derivatives: they come from whole 2x2 quads either way.
      const RectSplit split = splitRect(region.value_or(wholeFrame()), *shadows);
      for (const auto& [program, pieces] : {std::pair{groundProgram.get(), &split.inside},
                                            std::pair{litGroundProgram.get(), &split.outside}}) {
        if (pieces->empty()) continue;
        useGround(*program);
        for (const PixelRect& piece : *pieces) {
          if (program == litGroundProgram.get()) unshadowedFloor += piece.area();
          scissor(piece, supersample);
          gl.DrawArrays(GL_TRIANGLE_STRIP, 0, 4);
        }
      }
      scissor(region, supersample);
    } else {
      useGround(*groundProgram);
      gl.DrawArrays(GL_TRIANGLE_STRIP, 0, 4);
    }
    gl.Disable(GL_POLYGON_OFFSET_FILL);
  }
  lap(&PassTimes::floor);
}

void Renderer::Impl::presentPass(const DrawList& list, const std::optional<PixelRect>& region) {
  gl.BindFramebuffer(GL_FRAMEBUFFER, presentFbo);
  gl.Viewport(0, 0, settings.width, settings.height);
  gl.Disable(GL_DEPTH_TEST);
  // Where the floor covers every sample, the program that does not work out the sky.
  const PixelRect drawn = region.value_or(wholeFrame());
  const bool covered = settings.skipHiddenWork && floorPresentProgram && list.groundHeight &&
                       floorCovers(list.camera, settings.width, settings.height, *list.groundHeight,
                                   list.camera.position.head<2>(), groundHalfSide(list), drawn);
  ShaderProgram& presentProgram = covered ? *floorPresentProgram : *this->presentProgram;
  if (covered) skyFree += drawn.area();
  presentProgram.use();
  gl.ActiveTexture(samples > 1 ? GL_TEXTURE0 : GL_TEXTURE1);
  gl.BindTexture(samples > 1 ? GL_TEXTURE_2D_MULTISAMPLE : GL_TEXTURE_2D, sceneColor);
  gl.Uniform1i(presentProgram.uniform("uScene"), 0);
  gl.Uniform1i(presentProgram.uniform("uImage"), 1);
  gl.Uniform1i(presentProgram.uniform("uSamples"), samples);
  gl.Uniform1i(presentProgram.uniform("uSupersample"), supersample);
  // The sky: view rays from the camera's rotation alone (the sky is infinitely far).
  const Mat4 projection =
      list.camera.projectionMatrix(static_cast<double>(settings.width) / settings.height);
  Mat4 viewRotation = list.camera.viewMatrix();
  viewRotation.block<3, 1>(0, 3).setZero();
  setMatrix(gl, presentProgram.uniform("uInverseViewProjection"),
            Mat4((projection * viewRotation).inverse()));
  gl.Uniform2f(presentProgram.uniform("uSceneSize"), static_cast<float>(sceneWidth),
               static_cast<float>(sceneHeight));
  gl.Uniform1i(presentProgram.uniform("uDither"), settings.dither ? 1 : 0);
  gl.BindVertexArray(emptyVao);
  gl.DrawArrays(GL_TRIANGLES, 0, 3);
  lap(&PassTimes::present);
}

Renderer::Renderer(Context& context, const RenderSettings& settings)
    : impl_(std::make_unique<Impl>(context, settings)) {
  for (const auto& [side, pixels] :
       {std::pair<const char*, int>{"width", settings.width}, {"height", settings.height}}) {
    const std::string problem = frameSideProblem(side, pixels);
    if (!problem.empty()) throw GlError(problem);
  }
  Impl& r = *impl_;
  const std::string& dir = settings.shaderDir;
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
  // GL's rows run bottom to top; images run top to bottom.
  if (out.width != w || out.height != h) out = Image(w, h);
  out.alpha.resize(r.settings.alpha ? static_cast<std::size_t>(w) * h : 0);
  for (int y = 0; y < h; ++y) {
    const std::uint8_t* src = r.readback.data() + static_cast<std::size_t>(h - 1 - y) * w * 4;
    std::uint8_t* dst = out.pixel(0, y);
    for (int x = 0; x < w; ++x) {
      dst[3 * x + 0] = src[4 * x + 0];
      dst[3 * x + 1] = src[4 * x + 1];
      dst[3 * x + 2] = src[4 * x + 2];
    }
    if (r.settings.alpha) {
      std::uint8_t* a = out.alpha.data() + static_cast<std::size_t>(y) * w;
      for (int x = 0; x < w; ++x) a[x] = src[4 * x + 3];
    }
  }
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

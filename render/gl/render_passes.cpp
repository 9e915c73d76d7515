// The passes of a frame: the shadow map from the sun, the scene (bodies, terrain, trails and
// the floor) into the multisampled linear-light target, and the present pass into 8 bits.
#include <chrono>
#include <cmath>
#include <numbers>
#include <utility>

#include "render/gl/renderer_impl.h"
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
  const Vec3 sun = list.sunDirection.normalized();
  const SceneFrame frame{list, shadow, projection * view, sun, fillDirection(sun)};

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

  // Bodies and terrain first: the floor and the sky then only shade what is still visible.
  drawInstances(frame, region);
  lap(&PassTimes::scene);

  gl.BindVertexArray(emptyVao);
  if (list.groundHeight) drawFloor(frame, region);
  lap(&PassTimes::floor);
}

void Renderer::Impl::useCommon(ShaderProgram& p, const SceneFrame& frame) {
  const DrawList& list = frame.list;
  const ShadowProjection& shadow = frame.shadow;
  p.use();
  setMatrix(gl, p.uniform("uViewProjection"), frame.viewProjection);
  setVec3(gl, p.uniform("uCameraPos"), list.camera.position);
  setVec3(gl, p.uniform("uSunDir"), frame.sun);
  setVec3(gl, p.uniform("uFillDir"), frame.fill);
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
}

void Renderer::Impl::drawInstances(const SceneFrame& frame,
                                   const std::optional<PixelRect>& region) {
  const DrawList& list = frame.list;
  if (list.drape) {
    bindDrape(list);
    useCommon(*drapedSceneProgram, frame);
    const DrapeImage& d = *list.drape;
    gl.Uniform1i(drapedSceneProgram->uniform("uDrape"), 1);
    gl.Uniform4f(drapedSceneProgram->uniform("uDrapeRect"), static_cast<float>(d.x0),
                 static_cast<float>(d.y0), static_cast<float>(d.x1 - d.x0),
                 static_cast<float>(d.y1 - d.y0));
  }
  useCommon(*sceneProgram, frame);
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
}

void Renderer::Impl::drawFloor(const SceneFrame& frame, const std::optional<PixelRect>& region) {
  const DrawList& list = frame.list;
  const double half = groundHalfSide(list);
  const Eigen::Vector2d c = list.camera.position.head<2>();
  auto useGround = [&](ShaderProgram& p) {
    useCommon(p, frame);
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

}  // namespace vf::gl

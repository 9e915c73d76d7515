// The renderer's GPU resources: the shadow-map, scene and output framebuffers, the meshes
// uploaded once per DrawMesh key, and the draped picture's texture.
#include <cstdio>
#include <string>

#include "render/gl/renderer_impl.h"
#include "sim/shape/drape_import.h"

namespace vf::gl {
namespace {

void checkFramebuffer(const Api& gl, const char* what) {
  const GLenum status = gl.CheckFramebufferStatus(GL_FRAMEBUFFER);
  if (status != GL_FRAMEBUFFER_COMPLETE) {
    char code[16];
    std::snprintf(code, sizeof code, "0x%04X", status);
    throw GlError(std::string("could not make the ") + what + " framebuffer (status " + code + ")");
  }
}

}  // namespace

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

}  // namespace vf::gl

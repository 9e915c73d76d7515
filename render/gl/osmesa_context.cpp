// The OSMesa backend: the only file that includes osmesa.h.
#include <GL/osmesa.h>

#include <vector>

#include "render/gl/gl_context.h"

namespace vf::gl {
namespace {

class OsmesaContext final : public Context {
 public:
  OsmesaContext() {
    const int attributes[] = {OSMESA_FORMAT,
                              OSMESA_RGBA,
                              OSMESA_DEPTH_BITS,
                              0,
                              OSMESA_STENCIL_BITS,
                              0,
                              OSMESA_PROFILE,
                              OSMESA_CORE_PROFILE,
                              OSMESA_CONTEXT_MAJOR_VERSION,
                              4,
                              OSMESA_CONTEXT_MINOR_VERSION,
                              5,
                              0};
    context_ = OSMesaCreateContextAttribs(attributes, nullptr);
    if (!context_) {
      throw GlError(
          "could not create an OSMesa OpenGL 4.5 core context. Mesa's llvmpipe provides one "
          "(Debian 12: apt install libosmesa6); Mesa 25.1 and later no longer ship OSMesa, "
          "so try --gl egl");
    }
    try {
      makeCurrent();
      loadApi("OSMesa",
              [](const char* name) { return reinterpret_cast<void*>(OSMesaGetProcAddress(name)); });
    } catch (...) {
      OSMesaDestroyContext(context_);
      throw;
    }
  }
  ~OsmesaContext() override { OSMesaDestroyContext(context_); }

  void makeCurrent() override {
    // OSMesa insists on a colour buffer to make a context current; voxfall never draws to it
    // (frames go to framebuffer objects), so a tiny one will do.
    if (!OSMesaMakeCurrent(context_, buffer_.data(), GL_UNSIGNED_BYTE, kSize, kSize)) {
      throw GlError("OSMesaMakeCurrent failed");
    }
  }

 private:
  static constexpr int kSize = 4;
  OSMesaContext context_ = nullptr;
  std::vector<unsigned char> buffer_ = std::vector<unsigned char>(kSize * kSize * 4);
};

}  // namespace

std::unique_ptr<Context> createOsmesaContext() { return std::make_unique<OsmesaContext>(); }

}  // namespace vf::gl

// The EGL backend on Mesa's surfaceless platform: no window system, no display server. The
// only file that includes EGL headers.
#include <EGL/egl.h>
#include <EGL/eglext.h>

#include <cstdio>
#include <string>

#include "render/gl/gl_context.h"

namespace vf::gl {
namespace {

std::string eglErrorText(const char* what) {
  char code[16];
  std::snprintf(code, sizeof code, "0x%04X", static_cast<unsigned>(eglGetError()));
  return std::string(what) + " failed (EGL error " + code + ")";
}

class EglContext final : public Context {
 public:
  EglContext() {
    const char* clientExtensions = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
    if (!clientExtensions ||
        std::string(clientExtensions).find("EGL_MESA_platform_surfaceless") == std::string::npos) {
      throw GlError(
          "could not create an EGL context: this EGL has no EGL_MESA_platform_surfaceless "
          "(Debian 12: apt install libegl-mesa0); try --gl osmesa");
    }
    auto getPlatformDisplay = reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(
        eglGetProcAddress("eglGetPlatformDisplayEXT"));
    if (!getPlatformDisplay) {
      throw GlError("could not create an EGL context: no eglGetPlatformDisplayEXT");
    }
    display_ = getPlatformDisplay(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
    EGLint major = 0, minor = 0;
    if (display_ == EGL_NO_DISPLAY || !eglInitialize(display_, &major, &minor)) {
      throw GlError("could not create an EGL context: " + eglErrorText("eglInitialize") +
                    "; try --gl osmesa");
    }
    if (!eglBindAPI(EGL_OPENGL_API)) {
      eglTerminate(display_);
      throw GlError("could not create an EGL context: " + eglErrorText("eglBindAPI(OpenGL)"));
    }
    const EGLint attributes[] = {EGL_CONTEXT_MAJOR_VERSION,
                                 4,
                                 EGL_CONTEXT_MINOR_VERSION,
                                 5,
                                 EGL_CONTEXT_OPENGL_PROFILE_MASK,
                                 EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
                                 EGL_NONE};
    // No config and no surface (EGL_KHR_no_config_context, EGL_KHR_surfaceless_context):
    // every frame goes to framebuffer objects.
    context_ = eglCreateContext(display_, EGL_NO_CONFIG_KHR, EGL_NO_CONTEXT, attributes);
    if (context_ == EGL_NO_CONTEXT) {
      const std::string error = eglErrorText("eglCreateContext(OpenGL 4.5 core)");
      eglTerminate(display_);
      throw GlError("could not create an EGL context: " + error + "; try --gl osmesa");
    }
    try {
      makeCurrent();
      loadApi("EGL",
              [](const char* name) { return reinterpret_cast<void*>(eglGetProcAddress(name)); });
    } catch (...) {
      eglDestroyContext(display_, context_);
      eglTerminate(display_);
      throw;
    }
  }
  ~EglContext() override {
    eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    eglDestroyContext(display_, context_);
    eglTerminate(display_);
  }

  void makeCurrent() override {
    if (!eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, context_)) {
      throw GlError(eglErrorText("eglMakeCurrent"));
    }
  }

 private:
  EGLDisplay display_ = EGL_NO_DISPLAY;
  EGLContext context_ = EGL_NO_CONTEXT;
};

}  // namespace

std::unique_ptr<Context> createEglContext() { return std::make_unique<EglContext>(); }

}  // namespace vf::gl

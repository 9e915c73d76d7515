// An off-screen OpenGL 4.5 core context, behind one small interface so the backend can change
// (Mesa removed OSMesa in 25.1; EGL surfaceless gives the same llvmpipe pixels, or a GPU).
// No window and no X server either way: rendering goes to framebuffer objects.
#pragma once

#include <memory>
#include <stdexcept>
#include <string>

namespace vf::gl {

struct Api;

// The context could not be made, or a GL operation failed.
class GlError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

enum class Backend {
  osmesa,  // Mesa's off-screen library (default)
  egl,     // EGL on the surfaceless platform (EGL_MESA_platform_surfaceless)
};

// "osmesa" / "egl" -> Backend; throws GlError listing the valid names otherwise.
Backend parseBackend(const std::string& name);
const char* backendName(Backend backend);

class Context {
 public:
  virtual ~Context();
  Context(const Context&) = delete;
  Context& operator=(const Context&) = delete;

  // Makes this the calling thread's current context (done once on creation).
  virtual void makeCurrent() = 0;
  // The GL entry points of this context.
  const Api& api() const { return *api_; }
  // "OSMesa: 4.5 (Core Profile) Mesa 22.3.6, llvmpipe (LLVM 15.0.6, 256 bits)".
  const std::string& description() const { return description_; }

 protected:
  Context();
  // Loads the entry points with the backend's proc-address function and fills description().
  void loadApi(const char* backend, void* (*getProc)(const char*));

 private:
  std::unique_ptr<Api> api_;
  std::string description_;
};

// Creates and makes current a 4.5 core context; throws GlError with what failed and what to
// try instead.
std::unique_ptr<Context> createContext(Backend backend = Backend::osmesa);

// Backend constructors, one per file (each the only includer of its library's header).
std::unique_ptr<Context> createOsmesaContext();
std::unique_ptr<Context> createEglContext();

}  // namespace vf::gl

#include "render/gl/gl_context.h"

#include "render/gl/gl_api.h"

namespace vf::gl {

void Api::load(GetProc getProc) {
#define VF_GL_LOAD(type, name)                        \
  name = reinterpret_cast<type>(getProc("gl" #name)); \
  if (!name) throw GlError("OpenGL context lacks gl" #name " (an OpenGL 4.5 core function)");
  VF_GL_FUNCTIONS(VF_GL_LOAD)
#undef VF_GL_LOAD
}

Backend parseBackend(const std::string& name) {
  if (name == "osmesa") return Backend::osmesa;
  if (name == "egl") return Backend::egl;
  throw GlError("unknown GL backend '" + name + "': use 'osmesa' or 'egl'");
}

const char* backendName(Backend backend) { return backend == Backend::egl ? "egl" : "osmesa"; }

Context::Context() : api_(std::make_unique<Api>()) {}
Context::~Context() = default;

void Context::loadApi(const char* backend, void* (*getProc)(const char*)) {
  api_->load(getProc);
  const auto* version = reinterpret_cast<const char*>(api_->GetString(GL_VERSION));
  const auto* renderer = reinterpret_cast<const char*>(api_->GetString(GL_RENDERER));
  description_ =
      std::string(backend) + ": " + (version ? version : "?") + ", " + (renderer ? renderer : "?");
}

std::unique_ptr<Context> createContext(Backend backend) {
  return backend == Backend::egl ? createEglContext() : createOsmesaContext();
}

}  // namespace vf::gl

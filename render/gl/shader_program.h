// GLSL programs loaded at run time from shaders/ (sources are not compiled in, so
// the look can be changed without rebuilding). Errors name the file and line.
#pragma once

#include <map>
#include <string>
#include <vector>

namespace vf::gl {

struct Api;

// The folder the GLSL sources are read from, first match wins:
//   1. `explicitDir` when not empty (the --shaders option);
//   2. shaders/ next to the running executable, or ../share/voxfall/shaders from it (installed);
//   3. the source tree's shaders/ (VOXFALL_SHADER_DIR, set by CMake).
// Throws InputError saying where it looked when none holds the sources.
std::string findShaderDir(const std::string& explicitDir = "");

// A GLSL source with its `#include "file"` lines expanded (one level per include, from the same
// folder), and the files in source-string order: each part is introduced by `#line N K`, so
// the compiler's log reports "K:LINE(COL)" and K indexes `files`.
struct ShaderSource {
  std::string text;
  std::vector<std::string> files;  // files[0] is the main file
};
ShaderSource readShaderSource(const std::string& dir, const std::string& file);

// Rewrites a compiler log "K:LINE(COL): message" into "file:LINE:COL: message" lines. Returns
// the first error's "file:LINE" in `firstWhere` (empty if the log has no recognisable line).
std::string mapShaderLog(const std::string& log, const std::vector<std::string>& files,
                         std::string& firstWhere);

class ShaderProgram {
 public:
  // Reads, compiles and links dir/vertexFile + dir/fragmentFile, the fragment shader with a
  // `#define D` for each D of `fragmentDefines` (a variant of it). The GL context must be
  // current. Throws InputError("file:line", "GLSL compile error ...\n<log>") on a compile error,
  // InputError("vert + frag", "GLSL link error ...") on a link error.
  ShaderProgram(const Api& api, const std::string& dir, const std::string& vertexFile,
                const std::string& fragmentFile,
                const std::vector<std::string>& fragmentDefines = {});
  ~ShaderProgram();
  ShaderProgram(const ShaderProgram&) = delete;
  ShaderProgram& operator=(const ShaderProgram&) = delete;

  void use() const;
  // Location of a uniform; -1 when the program has none by that name (or it was optimised
  // away), which GL's glUniform* calls silently ignore.
  int uniform(const std::string& name);

 private:
  const Api* api_;
  unsigned id_ = 0;
  std::map<std::string, int> locations_;
};

}  // namespace vf::gl

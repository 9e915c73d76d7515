#include "render/gl/shader_program.h"

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>

#include "render/gl/gl_api.h"
#include "sim/core/error.h"

namespace vf::gl {
namespace fs = std::filesystem;

namespace {

// A file every shader folder holds: how a candidate folder is recognised.
constexpr const char* kMarkerFile = "scene.frag";

std::string readText(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path.string(), "cannot read shader source (does the file exist?)");
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

void expandIncludes(const std::string& dir, const std::string& file, int depth, ShaderSource& out) {
  if (depth > 8) throw InputError(file, "shader #include nested more than 8 deep (a cycle?)");
  const int index = static_cast<int>(out.files.size());
  out.files.push_back(file);
  const std::string text = readText(fs::path(dir) / file);
  static const std::regex include(R"(^\s*#\s*include\s+"([^"]+)\"\s*$)");
  std::istringstream lines(text);
  std::string line;
  int lineNo = 0;
  if (depth > 0) out.text += "#line 1 " + std::to_string(index) + "\n";
  while (std::getline(lines, line)) {
    ++lineNo;
    std::smatch m;
    if (std::regex_match(line, m, include)) {
      expandIncludes(dir, m[1].str(), depth + 1, out);
      // Back in this file: the next line is lineNo + 1 of source string `index`.
      out.text += "#line " + std::to_string(lineNo + 1) + " " + std::to_string(index) + "\n";
    } else {
      out.text += line;
      out.text += '\n';
    }
  }
}

}  // namespace

std::string findShaderDir(const std::string& explicitDir) {
  if (!explicitDir.empty()) {
    if (!fs::is_directory(explicitDir)) {
      throw InputError(explicitDir, "shader folder does not exist (--shaders)");
    }
    return explicitDir;
  }
  std::vector<fs::path> candidates;
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (!ec) {
    candidates.push_back(exe.parent_path() / "shaders");
    candidates.push_back(exe.parent_path() / ".." / "share" / "voxfall" / "shaders");
  }
#ifdef VOXFALL_SHADER_DIR
  candidates.emplace_back(VOXFALL_SHADER_DIR);
#endif
  std::string tried;
  for (const fs::path& dir : candidates) {
    if (fs::is_regular_file(dir / kMarkerFile, ec)) return dir.lexically_normal().string();
    tried += (tried.empty() ? "" : ", ") + dir.lexically_normal().string();
  }
  throw InputError("", "no GLSL shader folder found (looked in " + tried +
                           "); pass --shaders DIR pointing at voxfall's shaders/ folder");
}

ShaderSource readShaderSource(const std::string& dir, const std::string& file) {
  ShaderSource source;
  expandIncludes(dir, file, 0, source);
  return source;
}

std::string mapShaderLog(const std::string& log, const std::vector<std::string>& files,
                         std::string& firstWhere) {
  // Mesa writes "0:12(5): error: ..."; other drivers "0(12) : error ...".
  static const std::regex mesa(R"(^(\d+):(\d+)\((\d+)\):\s*(.*)$)");
  static const std::regex other(R"(^(\d+)\((\d+)\)\s*:\s*(.*)$)");
  firstWhere.clear();
  std::istringstream lines(log);
  std::string line, out;
  while (std::getline(lines, line)) {
    std::smatch m;
    std::string file, lineNo, column, message;
    if (std::regex_match(line, m, mesa)) {
      file = m[1].str(), lineNo = m[2].str(), column = m[3].str(), message = m[4].str();
    } else if (std::regex_match(line, m, other)) {
      file = m[1].str(), lineNo = m[2].str(), message = m[3].str();
    } else {
      if (!line.empty()) out += line + "\n";
      continue;
    }
    const std::size_t k = std::stoul(file);
    const std::string name = k < files.size() ? files[k] : "source " + file;
    const std::string where = name + ":" + lineNo;
    if (firstWhere.empty()) firstWhere = where;
    out += where + (column.empty() ? "" : ":" + column) + ": " + message + "\n";
  }
  return out;
}

namespace {

unsigned compileShader(const Api& gl, GLenum stage, const std::string& dir, const std::string& file,
                       const std::vector<std::string>& defines = {}) {
  ShaderSource source = readShaderSource(dir, file);
  if (!defines.empty()) {
    // After the #version line, which must come first; #line keeps the log's line numbers.
    std::string head;
    for (const std::string& d : defines) head += "#define " + d + "\n";
    const std::size_t eol = source.text.find('\n');
    const std::size_t at = eol == std::string::npos ? source.text.size() : eol + 1;
    source.text.insert(at, head + "#line 2 0\n");
  }
  const unsigned shader = gl.CreateShader(stage);
  const char* text = source.text.c_str();
  gl.ShaderSource(shader, 1, &text, nullptr);
  gl.CompileShader(shader);
  GLint ok = GL_FALSE;
  gl.GetShaderiv(shader, GL_COMPILE_STATUS, &ok);
  if (ok == GL_TRUE) return shader;
  GLint length = 0;
  gl.GetShaderiv(shader, GL_INFO_LOG_LENGTH, &length);
  std::string log(static_cast<std::size_t>(std::max(length, 1)), '\0');
  gl.GetShaderInfoLog(shader, length, nullptr, log.data());
  gl.DeleteShader(shader);
  log.resize(std::strlen(log.c_str()));
  std::string where;
  const std::string mapped = mapShaderLog(log, source.files, where);
  const fs::path full = fs::path(dir) / (where.empty() ? file : where);
  throw InputError(full.string(), "GLSL compile error in " + file + ":\n" + mapped);
}

}  // namespace

ShaderProgram::ShaderProgram(const Api& api, const std::string& dir, const std::string& vertexFile,
                             const std::string& fragmentFile,
                             const std::vector<std::string>& fragmentDefines)
    : api_(&api) {
  const unsigned vertex = compileShader(api, GL_VERTEX_SHADER, dir, vertexFile);
  unsigned fragment = 0;
  try {
    fragment = compileShader(api, GL_FRAGMENT_SHADER, dir, fragmentFile, fragmentDefines);
  } catch (...) {
    api.DeleteShader(vertex);
    throw;
  }
  id_ = api.CreateProgram();
  api.AttachShader(id_, vertex);
  api.AttachShader(id_, fragment);
  api.LinkProgram(id_);
  api.DeleteShader(vertex);  // flagged; freed with the program
  api.DeleteShader(fragment);
  GLint ok = GL_FALSE;
  api.GetProgramiv(id_, GL_LINK_STATUS, &ok);
  if (ok != GL_TRUE) {
    GLint length = 0;
    api.GetProgramiv(id_, GL_INFO_LOG_LENGTH, &length);
    std::string log(static_cast<std::size_t>(std::max(length, 1)), '\0');
    api.GetProgramInfoLog(id_, length, nullptr, log.data());
    api.DeleteProgram(id_);
    throw InputError((fs::path(dir) / vertexFile).string() + " + " + fragmentFile,
                     "GLSL link error:\n" + std::string(log.c_str()));
  }
}

ShaderProgram::~ShaderProgram() {
  if (id_) api_->DeleteProgram(id_);
}

void ShaderProgram::use() const { api_->UseProgram(id_); }

int ShaderProgram::uniform(const std::string& name) {
  auto it = locations_.find(name);
  if (it == locations_.end()) {
    it = locations_.emplace(name, api_->GetUniformLocation(id_, name.c_str())).first;
  }
  return it->second;
}

}  // namespace vf::gl

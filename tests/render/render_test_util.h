// Helpers shared by the render tests: synthetic shapes and bodies (no World needed), a
// scratch folder, running an external oracle (ffprobe), and the sRGB encoding restated.
#pragma once

#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>

#include "render/draw_list.h"
#include "sim/scene/scene.h"
#include "sim/shape/shape.h"

namespace vf::test {

// An axis-aligned box centred on the origin (outward CCW triangles), as a Shape.
inline std::shared_ptr<Shape> boxShape(const Vec3& half) {
  auto shape = std::make_shared<Shape>();
  shape->name = "box";
  for (int i = 0; i < 8; ++i) {
    shape->mesh.vertices.push_back(Vec3((i & 1) ? half.x() : -half.x(),
                                        (i & 2) ? half.y() : -half.y(),
                                        (i & 4) ? half.z() : -half.z()));
  }
  shape->mesh.triangles = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
                           {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
  shape->diameter = 2 * half.norm();
  return shape;
}

inline BodyView body(std::shared_ptr<const Shape> shape, const Vec3& x,
                     const Quat& q = Quat::Identity(), int colorId = 0) {
  BodyView b;
  b.shape = std::move(shape);
  b.x = x;
  b.q = q;
  b.color = defaultBodyColor(colorId);
  return b;
}

// A fresh, empty folder under the system temp folder, removed when the object goes.
class ScratchDir {
 public:
  explicit ScratchDir(const std::string& tag) {
    path_ = std::filesystem::temp_directory_path() /
            ("voxfall_" + tag + "_" + std::to_string(::getpid()));
    std::filesystem::remove_all(path_);
    std::filesystem::create_directories(path_);
  }
  ~ScratchDir() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
  }
  std::string file(const std::string& name) const { return (path_ / name).string(); }
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

// Temporary output files (OutputFile's ".NAME.partial-PID-N.EXT") left in `folder`.
inline int partialFiles(const std::filesystem::path& folder) {
  int n = 0;
  std::error_code ec;
  for (const auto& e : std::filesystem::directory_iterator(folder, ec))
    if (e.path().filename().string().find(".partial-") != std::string::npos) ++n;
  return n;
}

// Runs a shell command and returns its standard output.
inline std::string runCommand(const std::string& command, int* exitCode = nullptr) {
  std::string out;
  std::FILE* pipe = ::popen(command.c_str(), "r");
  if (!pipe) return out;
  char buffer[4096];
  std::size_t n;
  while ((n = std::fread(buffer, 1, sizeof buffer, pipe)) > 0) out.append(buffer, n);
  const int status = ::pclose(pipe);
  if (exitCode) *exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return out;
}

// IEC 61966-2-1 sRGB encoding of a linear value, to an 8-bit code (round to nearest).
inline int srgbByte(double linear) {
  linear = std::clamp(linear, 0.0, 1.0);
  const double encoded =
      linear <= 0.0031308 ? 12.92 * linear : 1.055 * std::pow(linear, 1 / 2.4) - 0.055;
  return static_cast<int>(std::lround(encoded * 255));
}

}  // namespace vf::test

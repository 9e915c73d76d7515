// Small closed meshes built in code for the geometry and shape tests, and a temporary
// directory helper. Test-only: the oracles in the tests never call these to compute answers.
#pragma once

#include <gtest/gtest.h>
#include <unistd.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "sim/core/math.h"
#include "sim/geometry/tri_mesh.h"

namespace vf::test {

// Axis-aligned box [lo, hi]: 8 vertices, 12 outward (CCW seen from outside) triangles.
// Vertex i has x = hi if bit 0 set, y = hi if bit 1, z = hi if bit 2.
inline TriMesh boxMesh(const Vec3& lo, const Vec3& hi) {
  TriMesh m;
  for (int i = 0; i < 8; ++i)
    m.vertices.emplace_back(i & 1 ? hi.x() : lo.x(), i & 2 ? hi.y() : lo.y(),
                            i & 4 ? hi.z() : lo.z());
  // Each face as a quad (CCW from outside), split along its first diagonal.
  const int quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6},   // z = lo, z = hi
                           {0, 1, 5, 4}, {2, 6, 7, 3},   // y = lo, y = hi
                           {0, 4, 6, 2}, {1, 3, 7, 5}};  // x = lo, x = hi
  for (const auto& q : quads) {
    m.triangles.push_back({std::uint32_t(q[0]), std::uint32_t(q[1]), std::uint32_t(q[2])});
    m.triangles.push_back({std::uint32_t(q[0]), std::uint32_t(q[2]), std::uint32_t(q[3])});
  }
  return m;
}

// A prism: the simple polygon `poly` (CCW in xy, star-shaped from poly[0]) extruded from z0 to
// z1. Caps are fans from poly[0].
inline TriMesh extrudedPolygon(const std::vector<Eigen::Vector2d>& poly, double z0, double z1) {
  TriMesh m;
  const auto n = static_cast<std::uint32_t>(poly.size());
  for (const auto& p : poly) m.vertices.emplace_back(p.x(), p.y(), z0);
  for (const auto& p : poly) m.vertices.emplace_back(p.x(), p.y(), z1);
  for (std::uint32_t i = 1; i + 1 < n; ++i) {
    m.triangles.push_back({0, i + 1, i});          // bottom, seen from -z
    m.triangles.push_back({n, n + i, n + i + 1});  // top, seen from +z
  }
  for (std::uint32_t i = 0; i < n; ++i) {
    const std::uint32_t j = (i + 1) % n;
    m.triangles.push_back({i, j, n + j});
    m.triangles.push_back({i, n + j, n + i});
  }
  return m;
}

// Icosphere of radius r: a regular icosahedron whose faces are split in 4, `subdivisions`
// times, with new vertices pushed onto the sphere. Every vertex lies on the sphere.
inline TriMesh icosphere(int subdivisions, double r) {
  const double t = (1 + std::sqrt(5.0)) / 2;
  TriMesh m;
  for (auto v : {Vec3(-1, t, 0), Vec3(1, t, 0), Vec3(-1, -t, 0), Vec3(1, -t, 0), Vec3(0, -1, t),
                 Vec3(0, 1, t), Vec3(0, -1, -t), Vec3(0, 1, -t), Vec3(t, 0, -1), Vec3(t, 0, 1),
                 Vec3(-t, 0, -1), Vec3(-t, 0, 1)})
    m.vertices.push_back(v.normalized() * r);
  m.triangles = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                 {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                 {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                 {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
  for (int s = 0; s < subdivisions; ++s) {
    std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> mid;
    auto midpoint = [&](std::uint32_t a, std::uint32_t b) {
      const auto key = std::minmax(a, b);
      auto it = mid.find(key);
      if (it != mid.end()) return it->second;
      const auto id = static_cast<std::uint32_t>(m.vertices.size());
      m.vertices.push_back((m.vertices[a] + m.vertices[b]).normalized() * r);
      mid.emplace(key, id);
      return id;
    };
    std::vector<std::array<std::uint32_t, 3>> next;
    for (const auto& f : m.triangles) {
      const std::uint32_t ab = midpoint(f[0], f[1]), bc = midpoint(f[1], f[2]),
                          ca = midpoint(f[2], f[0]);
      next.push_back({f[0], ab, ca});
      next.push_back({f[1], bc, ab});
      next.push_back({f[2], ca, bc});
      next.push_back({ab, bc, ca});
    }
    m.triangles = std::move(next);
  }
  return m;
}

// Signed volume by the divergence theorem with the field F = (x, 0, 0): div F = 1, so
// V = sum over triangles of the flux of F = sum (centroid x) * (area normal)_x. A different
// formula from the signed-tetrahedra code under test.
inline double fluxVolume(const TriMesh& m) {
  double v = 0;
  for (const auto& t : m.triangles) {
    const Vec3 &a = m.vertices[t[0]], &b = m.vertices[t[1]], &c = m.vertices[t[2]];
    const Vec3 areaNormal = 0.5 * (b - a).cross(c - a);
    v += (a.x() + b.x() + c.x()) / 3 * areaNormal.x();
  }
  return v;
}

// A fresh, empty directory for this test (name and pid make it unique when ctest runs test
// executables in parallel); removed on destruction.
class TempDir {
 public:
  TempDir() {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    path_ = std::filesystem::temp_directory_path() /
            ("voxfall_" + std::string(info->test_suite_name()) + "_" + info->name() + "_" +
             std::to_string(::getpid()));
    std::filesystem::remove_all(path_);
    std::filesystem::create_directories(path_);
  }
  ~TempDir() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
  }
  std::string file(const std::string& name) const { return (path_ / name).string(); }

 private:
  std::filesystem::path path_;
};

}  // namespace vf::test

// Smooth shading with a crease angle (render/smooth_normals.h). Oracle: a regular prism, whose
// side faces meet at 360/n degrees (soft below the crease) and meet the caps at 90 (hard): the
// smooth normal at a side vertex is the radial direction there by symmetry (each of its two side
// quads turns 90 degrees around it, whichever way the quads are cut into triangles), and a cap
// vertex's is the cap's own.
#include "render/smooth_normals.h"

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <numbers>

namespace vf {
namespace {

// A prism of `n` sides, radius 1, from z = 0 to z = 1, with fan caps; outward triangles.
TriMesh prism(int n) {
  TriMesh m;
  for (int k = 0; k < n; ++k) {
    const double a = 2 * std::numbers::pi * k / n;
    m.vertices.push_back(Vec3(std::cos(a), std::sin(a), 0));
    m.vertices.push_back(Vec3(std::cos(a), std::sin(a), 1));
  }
  const auto bottom = static_cast<std::uint32_t>(m.vertices.size());
  m.vertices.push_back(Vec3(0, 0, 0));
  m.vertices.push_back(Vec3(0, 0, 1));
  for (int k = 0; k < n; ++k) {
    const auto b0 = static_cast<std::uint32_t>(2 * k), t0 = b0 + 1;
    const auto b1 = static_cast<std::uint32_t>(2 * ((k + 1) % n)), t1 = b1 + 1;
    m.triangles.push_back({b0, b1, t1});
    m.triangles.push_back({b0, t1, t0});
    m.triangles.push_back({bottom, b1, b0});
    m.triangles.push_back({bottom + 1, t0, t1});
  }
  return m;
}

Vec3 faceNormal(const TriMesh& m, std::size_t t) {
  const auto& tri = m.triangles[t];
  return (m.vertices[tri[1]] - m.vertices[tri[0]])
      .cross(m.vertices[tri[2]] - m.vertices[tri[0]])
      .normalized();
}

TEST(SmoothNormals, UnitAndContinuousAcrossSoftEdgesSplitAcrossHardOnes) {
  const int n = 16;  // side faces meet at 22.5 degrees
  const TriMesh mesh = prism(n);
  const CreasedMesh c = creasedNormals(mesh, 30);
  ASSERT_EQ(c.normals.size(), c.mesh.vertices.size());
  ASSERT_EQ(c.mesh.triangles.size(), mesh.triangles.size());
  for (const Vec3& v : c.normals) EXPECT_NEAR(v.norm(), 1, 1e-12);
  // Every ring vertex becomes two: one for the sides, one for its cap; the cap centres stay.
  EXPECT_EQ(c.mesh.vertices.size(), 2 * mesh.vertices.size() - 2);
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const bool side = std::abs(faceNormal(mesh, t).z()) < 1e-9;
    for (int corner = 0; corner < 3; ++corner) {
      const std::uint32_t was = mesh.triangles[t][corner], is = c.mesh.triangles[t][corner];
      const Vec3& p = mesh.vertices[was];
      EXPECT_EQ(c.mesh.vertices[is], p) << "positions keep their values";
      const Vec3 expected = side ? Vec3(p.x(), p.y(), 0).normalized() : faceNormal(mesh, t);
      EXPECT_LT((c.normals[is] - expected).norm(), 1e-12)
          << "triangle " << t << " corner " << corner << (side ? " (side)" : " (cap)");
    }
  }
  // Continuous across a soft edge: the two side faces on either side of a vertical edge use
  // the same vertices there. Split across a hard edge: a cap triangle and a side triangle that
  // share an edge's positions use different vertices with normals 90 degrees apart.
  std::map<std::pair<std::uint32_t, bool>, std::uint32_t> seen;  // (old vertex, side?) -> new
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const bool side = std::abs(faceNormal(mesh, t).z()) < 1e-9;
    for (int corner = 0; corner < 3; ++corner) {
      const auto key = std::make_pair(mesh.triangles[t][corner], side);
      const auto [it, added] = seen.emplace(key, c.mesh.triangles[t][corner]);
      EXPECT_EQ(it->second, c.mesh.triangles[t][corner]) << "one vertex per smooth group";
    }
  }
  for (std::uint32_t v = 0; v < 2 * n; ++v) {
    const std::uint32_t sideCopy = seen.at({v, true}), capCopy = seen.at({v, false});
    EXPECT_NE(sideCopy, capCopy);
    EXPECT_NEAR(c.normals[sideCopy].dot(c.normals[capCopy]), 0, 1e-12);
  }
}

TEST(SmoothNormals, CreaseBelowTheFaceAngleIsFlatAndAboveAllIsOneNormal) {
  const TriMesh mesh = prism(16);
  // 20 degrees: sides (22.5 apart) stay hard, so every triangle's corners carry its own face
  // normal, as flat shading does, and only the two coplanar triangles of a quad share.
  const CreasedMesh flat = creasedNormals(mesh, 20);
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t)
    for (const std::uint32_t v : flat.mesh.triangles[t])
      EXPECT_LT((flat.normals[v] - faceNormal(mesh, t)).norm(), 1e-12) << t;
  // 180: nothing is hard; the mesh keeps its vertices, with smoothVertexNormals' normals.
  const CreasedMesh all = creasedNormals(mesh, 180);
  EXPECT_EQ(all.mesh.vertices.size(), mesh.vertices.size());
  const std::vector<Vec3> smooth = smoothVertexNormals(mesh);
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t)
    for (int c = 0; c < 3; ++c)
      EXPECT_LT((all.normals[all.mesh.triangles[t][c]] - smooth[mesh.triangles[t][c]]).norm(),
                1e-12);
}

}  // namespace
}  // namespace vf

// validateClosedMesh: each rejection (too few triangles, degenerate, open, non-manifold,
// inconsistent orientation, flat) names the file, counts, one example; inward meshes are
// flipped; valid meshes of any scale pass.
#include "sim/geometry/mesh_checks.h"

#include <gtest/gtest.h>

#include <string>

#include "sim/core/error.h"
#include "sim/geometry/mass_properties.h"
#include "tests/sim/test_meshes.h"

namespace vf {
namespace {

const std::string kWhere = "meshes/thing.obj";

// The message validateClosedMesh throws for `m` ("" and a failure if it accepts the mesh).
std::string rejection(TriMesh m) {
  try {
    validateClosedMesh(m, kWhere);
  } catch (const InputError& e) {
    EXPECT_EQ(e.where(), kWhere);
    EXPECT_NE(std::string(e.what()).find(kWhere), std::string::npos);
    return e.message();
  }
  ADD_FAILURE() << "mesh accepted";
  return "";
}

bool contains(const std::string& s, const std::string& part) {
  return s.find(part) != std::string::npos;
}

TEST(MeshChecks, ValidMeshesOfAnyScalePass) {
  // Thresholds are relative to the bounding box: a 0.1 mm box and a 10 km box both pass.
  for (double s : {1e-4, 1.0, 1e4}) {
    TriMesh m = test::boxMesh(Vec3(0, 0, 0), Vec3(s, 2 * s, 3 * s));
    const auto before = m.triangles;
    EXPECT_NO_THROW(validateClosedMesh(m, kWhere)) << s;
    EXPECT_EQ(m.triangles, before);  // already outward: untouched
  }
  TriMesh sphere = test::icosphere(2, 1.0);
  EXPECT_NO_THROW(validateClosedMesh(sphere, kWhere));
}

TEST(MeshChecks, TooFewTriangles) {
  TriMesh m;
  m.vertices = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)};
  m.triangles = {{0, 1, 2}, {0, 2, 1}};  // a closed but flat "pillow"
  const std::string msg = rejection(m);
  EXPECT_TRUE(contains(msg, "2 triangles")) << msg;
  EXPECT_TRUE(contains(msg, "at least 4")) << msg;
}

TEST(MeshChecks, OpenMesh) {
  TriMesh m = test::boxMesh(Vec3(0, 0, 0), Vec3(1, 1, 1));
  m.triangles.pop_back();  // a hole bounded by the removed triangle's 3 edges
  const std::string msg = rejection(m);
  EXPECT_TRUE(contains(msg, "not closed")) << msg;
  EXPECT_TRUE(contains(msg, "3 boundary edges")) << msg;
  EXPECT_TRUE(contains(msg, "between vertices")) << msg;
  EXPECT_TRUE(contains(msg, "watertight")) << msg;
}

TEST(MeshChecks, DegenerateTriangle) {
  // A closed box plus a zero-area sliver on an edge (collinear, not repeated, vertices).
  TriMesh m = test::boxMesh(Vec3(0, 0, 0), Vec3(1, 1, 1));
  m.vertices.push_back(0.5 * (m.vertices[0] + m.vertices[1]));
  m.triangles.push_back({0, 8, 1});
  std::string msg = rejection(m);
  EXPECT_TRUE(contains(msg, "1 degenerate")) << msg;
  EXPECT_TRUE(contains(msg, "triangle 12")) << msg;
  // A repeated index is degenerate too (caught before the edge checks get confused by it).
  m = test::boxMesh(Vec3(0, 0, 0), Vec3(1, 1, 1));
  m.triangles[5] = {3, 3, 7};
  msg = rejection(m);
  EXPECT_TRUE(contains(msg, "degenerate")) << msg;
  EXPECT_TRUE(contains(msg, "triangle 5")) << msg;
}

TEST(MeshChecks, NonManifoldEdge) {
  // Two boxes sharing only the edge x = y = 1 (welded): that edge has 4 triangles.
  TriMesh m = test::boxMesh(Vec3(0, 0, 0), Vec3(1, 1, 1));
  const TriMesh b = test::boxMesh(Vec3(1, 1, 0), Vec3(2, 2, 1));
  // b's vertices 0 (1,1,0) and 4 (1,1,1) coincide with a's 3 and 7.
  const std::uint32_t remap[8] = {3, 8, 9, 10, 7, 11, 12, 13};
  for (int i : {1, 2, 3, 5, 6, 7}) m.vertices.push_back(b.vertices[i]);
  for (auto t : b.triangles) m.triangles.push_back({remap[t[0]], remap[t[1]], remap[t[2]]});
  const std::string msg = rejection(m);
  EXPECT_TRUE(contains(msg, "not manifold")) << msg;
  EXPECT_TRUE(contains(msg, "between vertices 3 and 7")) << msg;
}

TEST(MeshChecks, InconsistentOrientation) {
  TriMesh m = test::boxMesh(Vec3(0, 0, 0), Vec3(1, 1, 1));
  std::swap(m.triangles[4][1], m.triangles[4][2]);  // one triangle wound the wrong way
  const std::string msg = rejection(m);
  EXPECT_TRUE(contains(msg, "inconsistently oriented")) << msg;
  EXPECT_TRUE(contains(msg, "3 edges")) << msg;  // each of its edges now disagrees
}

TEST(MeshChecks, InwardMeshIsFlipped) {
  TriMesh m = test::extrudedPolygon({{1, 1}, {1, 3}, {0, 3}, {0, 0}, {2, 0}, {2, 1}}, 0, 1);
  for (auto& t : m.triangles) std::swap(t[0], t[1]);
  ASSERT_LT(test::fluxVolume(m), 0);
  ASSERT_NO_THROW(validateClosedMesh(m, kWhere));
  // The L's cross-section has area 2 + 2, height 1: volume 4 (round-off ~1e-15).
  EXPECT_NEAR(test::fluxVolume(m), 4.0, 1e-12);
  EXPECT_NEAR(computeMassProperties(m, 1.0).volume, 4.0, 1e-12);
}

TEST(MeshChecks, FlatClosedMeshHasNoVolume) {
  // A unit square as a closed, consistently oriented double layer: top split along 0-2,
  // bottom along 1-3, so no edge has more than two triangles. Volume 0.
  TriMesh m;
  m.vertices = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(0, 1, 0)};
  m.triangles = {{0, 1, 2}, {0, 2, 3}, {0, 3, 1}, {1, 3, 2}};
  const std::string msg = rejection(m);
  EXPECT_TRUE(contains(msg, "no volume")) << msg;
  EXPECT_TRUE(contains(msg, "flat")) << msg;
}

}  // namespace
}  // namespace vf

// repairMesh (CGAL polygon mesh processing): each fault it fixes, built by hand in a mesh whose
// volume is known, is fixed to a closed mesh that validateClosedMesh accepts, with the volume
// of the intact mesh to a tolerance derived in the test; holes over the limits are refused; a
// scene without `repair` names the option. Volumes are computed here by the divergence theorem
// (independent of the code under test).
#include "sim/geometry/mesh_repair.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <numbers>
#include <set>
#include <string>

#include "sim/core/error.h"
#include "sim/geometry/mesh_checks.h"
#include "sim/geometry/mesh_import.h"
#include "sim/scene/scene.h"
#include "tests/sim/test_meshes.h"

namespace vf {
namespace {

double volumeOf(const TriMesh& m) {
  double v6 = 0;
  for (const auto& t : m.triangles)
    v6 += m.vertices[t[0]].dot(m.vertices[t[1]].cross(m.vertices[t[2]]));
  return v6 / 6;
}

// Repairs, checks the result is closed (validateClosedMesh) and returns it.
TriMesh repaired(const TriMesh& m, RepairReport& report, const RepairLimits& limits = {}) {
  TriMesh out = repairMesh(m, "thing.obj", report, limits);
  TriMesh checked = out;
  validateClosedMesh(checked, "thing.obj");
  EXPECT_EQ(checked.triangles, out.triangles) << "repair should leave the mesh facing outward";
  return out;
}

std::string refusal(const TriMesh& m, const RepairLimits& limits = {}) {
  RepairReport report;
  try {
    repairMesh(m, "thing.obj", report, limits);
  } catch (const InputError& e) {
    EXPECT_EQ(e.where(), "thing.obj");
    return e.message();
  }
  return "";
}

const Vec3 kLo(0, 0, 0), kHi(1, 2, 3);  // box volume 6

TEST(MeshRepair, ABoxWithOneTriangleRemovedGetsItBack) {
  TriMesh m = test::boxMesh(kLo, kHi);
  m.triangles.erase(m.triangles.begin() + 3);  // half of the z = hi face
  RepairReport report;
  const TriMesh r = repaired(m, report);
  // A three-edge hole has exactly one triangulation: the removed triangle; volume exact.
  EXPECT_EQ(report.holesFilled, 1u);
  EXPECT_EQ(report.patchTriangles, 1u);
  EXPECT_NEAR(report.patchArea, 0.5 * 1 * 2, 1e-12);
  EXPECT_EQ(r.triangles.size(), 12u);
  EXPECT_NEAR(volumeOf(r), 6.0, 1e-12);
  EXPECT_NE(report.summary().find("filled 1 hole with 1 triangle"), std::string::npos)
      << report.summary();
}

TEST(MeshRepair, FlippedDuplicateAndRepeatedVertexTrianglesAreFixed) {
  TriMesh m = test::boxMesh(kLo, kHi);
  std::swap(m.triangles[2][1], m.triangles[2][2]);  // the z = hi face's two triangles flipped
  std::swap(m.triangles[3][1], m.triangles[3][2]);
  m.triangles.push_back(m.triangles[5]);  // a duplicate
  m.triangles.push_back({0, 0, 1});       // a triangle that repeats a vertex
  RepairReport report;
  const TriMesh r = repaired(m, report);
  EXPECT_EQ(report.reorientedTriangles, 2u);
  EXPECT_EQ(report.duplicateTriangles, 1u);
  EXPECT_EQ(report.degenerateTriangles, 1u);
  EXPECT_EQ(report.holesFilled, 0u);
  EXPECT_EQ(r.triangles.size(), 12u);
  EXPECT_NEAR(volumeOf(r), 6.0, 1e-12);
}

TEST(MeshRepair, AZeroAreaSliverIsRemoved) {
  // The z = hi face (triangles {4,5,7}, {4,7,6}) with its second triangle split at the midpoint
  // m of the diagonal 4-7, and the sliver (4, 7, m) of zero area closing the fan: a closed mesh
  // that validateClosedMesh refuses as degenerate.
  TriMesh m = test::boxMesh(kLo, kHi);
  const auto mid = static_cast<std::uint32_t>(m.vertices.size());
  m.vertices.push_back(0.5 * (m.vertices[4] + m.vertices[7]));
  m.triangles[3] = {4, mid, 6};
  m.triangles.push_back({mid, 7, 6});
  m.triangles.push_back({4, 7, mid});
  TriMesh copy = m;
  EXPECT_THROW(validateClosedMesh(copy, "thing.obj"), InputError);
  RepairReport report;
  const TriMesh r = repaired(m, report);
  EXPECT_EQ(report.degenerateTriangles, 1u);
  EXPECT_NEAR(volumeOf(r), 6.0, 1e-12);
}

TEST(MeshRepair, AHoleInAClosedScanIsFilledCloseToTheOriginalVolume) {
  // spot.obj is closed. Removing the fan of triangles around one vertex leaves a hole whose
  // boundary is the fan's rim; the patch spans the rim. Both the removed fan and the patch lie
  // in the ball of radius rho (the longest fan edge) around the removed vertex, so the volume
  // between them is at most that ball's volume (4/3) pi rho^3.
  TriMesh spot = importMesh(VOXFALL_TEST_DATA_DIR "/spot.obj");
  validateClosedMesh(spot, "spot.obj");
  const double original = volumeOf(spot);
  const std::uint32_t centre = 100;
  TriMesh holed = spot;
  holed.triangles.clear();
  double rho = 0;
  std::size_t removed = 0;
  for (const auto& t : spot.triangles) {
    if (t[0] == centre || t[1] == centre || t[2] == centre) {
      for (std::uint32_t v : t)
        rho = std::max(rho, (spot.vertices[v] - spot.vertices[centre]).norm());
      ++removed;
    } else {
      holed.triangles.push_back(t);
    }
  }
  ASSERT_GE(removed, 4u);
  RepairReport report;
  const TriMesh r = repaired(holed, report);
  EXPECT_EQ(report.holesFilled, 1u);
  EXPECT_EQ(report.patchTriangles, removed - 2) << "a k-gon takes k - 2 triangles";
  EXPECT_NEAR(volumeOf(r), original, 4.0 / 3.0 * std::numbers::pi * rho * rho * rho);
  EXPECT_GT(std::abs(volumeOf(holed) - original), 0.0);
}

TEST(MeshRepair, TheStanfordBunnyScanWithHolesIsClosed) {
  // The low-resolution zipper reconstruction has several holes; each patch's volume is bounded
  // like a cone over its area: |V_repaired - V_open(c)| <= A_patch * R / 3, with V_open(c) the
  // open mesh's signed volume about its bounding-box centre c and R the largest distance of a
  // vertex from c (every patch triangle's plane is at most R from c).
  TriMesh bunny = importMesh(VOXFALL_TEST_DATA_DIR "/stanford_bunny_zipper_res3.ply");
  try {
    TriMesh copy = bunny;
    validateClosedMesh(copy, "bunny.ply");
    FAIL() << "the bunny should have holes";
  } catch (const InputError& e) {
    EXPECT_NE(e.message().find("not closed"), std::string::npos) << e.message();
  }
  const Vec3 c = bunny.bounds().center();
  TriMesh centred = bunny;
  centred.translate(-c);
  double R = 0;
  for (const Vec3& v : centred.vertices) R = std::max(R, v.norm());
  RepairReport report;
  TriMesh r = repaired(centred, report);
  EXPECT_GE(report.holesFilled, 1u);
  EXPECT_LE(report.largestPatchFraction, 0.05);
  const double open = volumeOf(centred);
  EXPECT_NEAR(std::abs(volumeOf(r)), std::abs(open), report.patchArea * R / 3);
  EXPECT_GT(volumeOf(r), 0.0) << "outward";
  std::printf("bunny: %s; volume %.6g (open mesh about its centre %.6g)\n",
              report.summary().c_str(), volumeOf(r), open);
}

TEST(MeshRepair, HolesOverTheLimitsAreRefused) {
  TriMesh m = test::boxMesh(kLo, kHi);
  m.triangles.erase(m.triangles.begin() + 2, m.triangles.begin() + 4);  // the whole z = hi face
  // The patch is the 1 x 2 face: 2 / 22 of the surface (faces of 2, 2, 3, 3, 6 and 6), over 5 %.
  const std::string msg = refusal(m);
  EXPECT_NE(msg.find("hole of 4 boundary edges whose patch would cover 9.1 %"), std::string::npos)
      << msg;
  RepairLimits wide;
  wide.maxHoleAreaFraction = 0.1;
  EXPECT_EQ(refusal(m, wide), "");
  RepairLimits few;
  few.maxHoleEdges = 3;
  EXPECT_NE(refusal(m, few).find("hole of 4 boundary edges, more than the 3"), std::string::npos);
}

// A scene whose shape's mesh is a 0.2 x 0.2 x 1 m box with one triangle missing (0.02 m^2 of
// 0.88 m^2: a patch of 2.3 %, within repair's 5 %).
std::string writeHoledBoxScene(const test::TempDir& dir, bool repair) {
  TriMesh m = test::boxMesh(kLo, Vec3(0.2, 0.2, 1.0));
  m.triangles.erase(m.triangles.begin() + 3);
  std::ofstream obj(dir.file("holed.obj"));
  for (const Vec3& v : m.vertices) obj << "v " << v.x() << " " << v.y() << " " << v.z() << "\n";
  for (const auto& t : m.triangles)
    obj << "f " << t[0] + 1 << " " << t[1] + 1 << " " << t[2] + 1 << "\n";
  obj.close();
  const std::string path = dir.file(repair ? "repair.toml" : "plain.toml");
  std::ofstream scene(path);
  scene << "[simulation]\nduration = 0.1\nlevel = 2\n[ground]\nplane = 0.0\n"
        << "[shapes.box]\nmesh = \"holed.obj\"\ndensity = 800\n"
        << (repair ? "repair = true\n" : "") << "[[bodies]]\nshape = \"box\"\n"
        << "position = [0.0, 0.0, 1.0]\n";
  return path;
}

TEST(MeshRepair, SceneErrorNamesTheRepairOptionAndRepairBuildsIt) {
  const test::TempDir dir;
  try {
    buildScene(loadScene(writeHoledBoxScene(dir, false)));
    FAIL() << "an open mesh should be refused";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("not closed"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("repair = true on [shapes.box]"), std::string::npos)
        << e.what();
    EXPECT_NE(std::string(e.what()).find("--repair"), std::string::npos) << e.what();
  }
  const BuiltScene built = buildScene(loadScene(writeHoledBoxScene(dir, true)));
  ASSERT_EQ(built.world->bodyCount(), 1);
  // assimp reads coordinates as floats (relative rounding 6e-8 each, three in a volume).
  EXPECT_NEAR(built.world->shape(0).volume, 0.04, 0.04 * 2e-7);
}

}  // namespace
}  // namespace vf

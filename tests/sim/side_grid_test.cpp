// SideGrid against the brute-force reference (the generalised winding number of
// sim/geometry/mesh_query.h): wherever the grid decides a side, the winding number agrees, on
// random points, on points just off the surface, and through pointInsideBody in world poses;
// and the grid does decide where it should (the barrel's cavity, the cross's core).
#include "sim/shape/side_grid.h"

#include <gtest/gtest.h>

#include <string>

#include "sim/collide/penetration.h"
#include "sim/core/prng.h"
#include "sim/geometry/mesh_bvh.h"
#include "sim/geometry/mesh_import.h"
#include "sim/geometry/mesh_query.h"
#include "sim/shape/shape.h"
#include "tests/sim/test_meshes.h"

namespace vf {
namespace {

using Side = SideGrid::Side;

TriMesh sceneMesh(const std::string& name) {
  return importMesh(std::string(VOXFALL_SOURCE_DIR) + "/scenes/meshes/" + name);
}

struct GridCase {
  const char* mesh;
  int cells;
};

class SideGridOnSceneMeshes : public ::testing::TestWithParam<GridCase> {};

// Random points over the bounds and a margin around them: a decided side is the winding
// number's. (The winding number is decided only away from the surface; every decided point is
// at least half a cell from it, far beyond its round-off, so all of them are compared.)
TEST_P(SideGridOnSceneMeshes, DecidedSidesAreTheWindingNumbers) {
  const TriMesh mesh = sceneMesh(GetParam().mesh);
  const MeshBvh bvh(mesh);
  const SideGrid grid(mesh, bvh, GetParam().cells);
  const auto box = mesh.bounds();
  const Vec3 margin = 0.1 * box.sizes();
  Prng rng(23);
  int outside = 0, near = 0;
  for (int i = 0; i < 4000; ++i) {
    Vec3 p;
    for (int k = 0; k < 3; ++k)
      p[k] = rng.uniform(box.min()[k] - margin[k], box.max()[k] + margin[k]);
    const Side s = grid.side(p);
    if (s == Side::kNearSurface) {
      ++near;
      continue;
    }
    EXPECT_EQ(s == Side::kInside, pointInsideMesh(mesh, p)) << p.transpose();
    outside += s == Side::kOutside;
  }
  EXPECT_GT(outside, 0);
  EXPECT_GT(near, 0) << "the surface's cells are never decided";
}

// Points a hair off every face, on both sides, are left to the exact search.
TEST_P(SideGridOnSceneMeshes, PointsJustOffTheSurface) {
  const TriMesh mesh = sceneMesh(GetParam().mesh);
  const MeshBvh bvh(mesh);
  const SideGrid grid(mesh, bvh, GetParam().cells);
  const auto box = mesh.bounds();
  const double size = box.sizes().maxCoeff();
  Prng rng(31);
  for (const auto& t : mesh.triangles) {
    const Vec3 &a = mesh.vertices[t[0]], &b = mesh.vertices[t[1]], &c = mesh.vertices[t[2]];
    const Vec3 n = (b - a).cross(c - a).normalized();
    for (int k = 0; k < 5; ++k) {
      double u = rng.uniform(0, 1), v = rng.uniform(0, 1);
      if (u + v > 1) u = 1 - u, v = 1 - v;
      const Vec3 on = a + u * (b - a) + v * (c - a);
      for (const double offset : {1e-6 * size, -1e-6 * size}) {
        const Vec3 p = on + offset * n;
        // Beyond the bounds: outside. Within them its cell, widened by the margin, touches the
        // face: never decided.
        const Side expected = box.contains(p) ? Side::kNearSurface : Side::kOutside;
        EXPECT_EQ(grid.side(p), expected) << p.transpose();
      }
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Meshes, SideGridOnSceneMeshes,
                         ::testing::Values(GridCase{"cross.obj", 32}, GridCase{"barrel.obj", 32},
                                           GridCase{"barrel.obj", 7},
                                           GridCase{"highpoly_block.obj", 32},
                                           GridCase{"rock.obj", 32}, GridCase{"rock.obj", 64},
                                           GridCase{"stack_block.obj", 1}));

// Where the grid must decide: the middle of the barrel's cavity is outside the solid (the
// barrel is open-topped, 0.9 m across with a wall of about 6 cm in the unit-scaled file), the
// cross's core is inside it; a grid of one cell decides nothing.
TEST(SideGrid, DecidesTheCavityAndTheCore) {
  const TriMesh barrel = sceneMesh("barrel.obj");
  const SideGrid barrelGrid(barrel, MeshBvh(barrel));
  const auto b = barrel.bounds();
  EXPECT_EQ(barrelGrid.side(b.center()), Side::kOutside);
  EXPECT_FALSE(pointInsideMesh(barrel, b.center()));

  const TriMesh cross = sceneMesh("cross.obj");
  const SideGrid crossGrid(cross, MeshBvh(cross));
  const Vec3 core = cross.bounds().center();
  ASSERT_TRUE(pointInsideMesh(cross, core));
  EXPECT_EQ(crossGrid.side(core), Side::kInside);
  EXPECT_EQ(crossGrid.side(cross.bounds().max() + Vec3::Constant(1e-3)), Side::kOutside);

  const SideGrid one(cross, MeshBvh(cross), 1);
  EXPECT_EQ(one.side(core), Side::kNearSurface);
  EXPECT_EQ(one.cells(), (std::array<int, 3>{1, 1, 1}));
}

// A hollow box (a closed cavity: an inner box wound inwards): the cavity is a group of cells
// that no outside cell reaches, and it is outside the solid; the wall between is inside.
TEST(SideGrid, AClosedCavityIsOutsideAndTheWallInside) {
  TriMesh hollow = test::boxMesh(Vec3(0, 0, 0), Vec3(1, 1, 1));
  const TriMesh inner = test::boxMesh(Vec3(0.25, 0.25, 0.25), Vec3(0.75, 0.75, 0.75));
  const auto offset = static_cast<std::uint32_t>(hollow.vertices.size());
  hollow.vertices.insert(hollow.vertices.end(), inner.vertices.begin(), inner.vertices.end());
  for (const auto& t : inner.triangles)
    hollow.triangles.push_back({t[0] + offset, t[2] + offset, t[1] + offset});  // inwards
  const SideGrid grid(hollow, MeshBvh(hollow), 16);
  EXPECT_EQ(grid.side(Vec3(0.5, 0.5, 0.5)), Side::kOutside);   // the cavity
  EXPECT_EQ(grid.side(Vec3(0.125, 0.5, 0.5)), Side::kInside);  // the wall
  EXPECT_EQ(grid.side(Vec3(0.5, 0.875, 0.5)), Side::kInside);
  EXPECT_EQ(grid.side(Vec3(0.01, 0.5, 0.5)), Side::kNearSurface);
  Prng rng(3);
  for (int i = 0; i < 2000; ++i) {
    const Vec3 p(rng.uniform(0, 1), rng.uniform(0, 1), rng.uniform(0, 1));
    const Side s = grid.side(p);
    if (s == Side::kNearSurface) continue;
    EXPECT_EQ(s == Side::kInside, pointInsideMesh(hollow, p)) << p.transpose();
  }
}

// pointInsideBody, which asks the grid first, against the winding number in world poses.
TEST(SideGrid, PointInsideBodyAgreesWithTheWindingNumberInWorldPoses) {
  Prng rng(41);
  for (const char* name : {"barrel.obj", "cross.obj"}) {
    const auto shape = makeShape(name, sceneMesh(name), Vec3::Ones(), 800, 2);
    const auto box = shape->mesh.bounds();
    int inside = 0;
    for (int i = 0; i < 20; ++i) {
      const Quat q =
          Quat(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1))
              .normalized();
      const Pose pose{Vec3(rng.uniform(-50, 50), rng.uniform(-50, 50), rng.uniform(0, 9)), q};
      for (int k = 0; k < 100; ++k) {
        Vec3 local;
        for (int c = 0; c < 3; ++c) local[c] = rng.uniform(box.min()[c], box.max()[c]);
        const Vec3 world = pose.x + q * local;
        const Vec3 back = q.conjugate() * (world - pose.x);  // as pointInsideBody computes it
        if (distanceToMesh(shape->mesh, back) < 1e-9) continue;
        const bool in = pointInsideMesh(shape->mesh, back);
        EXPECT_EQ(pointInsideBody(*shape, pose, world), in) << name << " " << local.transpose();
        inside += in;
      }
    }
    EXPECT_GT(inside, 50) << name << ": both outcomes occur";
  }
}

}  // namespace
}  // namespace vf

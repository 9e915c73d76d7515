// buildSphereTree: closed-form voxel counts for a cube, tree structure invariants, exactness
// of the surface voxel set against a brute-force full grid, coverage of surface samples,
// the bounding sphere, determinism.
#include "sim/shape/sphere_tree.h"

#include <gtest/gtest.h>

#include <cmath>
#include <set>
#include <tuple>

#include "sim/core/prng.h"
#include "sim/geometry/mesh_import.h"
#include "sim/geometry/mesh_query.h"
#include "sim/shape/shape.h"
#include "sim/shape/voxelize.h"
#include "tests/sim/test_meshes.h"

namespace vf {
namespace {

// Structural invariants every tree must satisfy; `mesh` is the mesh it was built from.
void expectWellFormed(const SphereTree& tree, const TriMesh& mesh, int leafLevel) {
  ASSERT_EQ(tree.leafLevel(), leafLevel);
  ASSERT_EQ(tree.levels[0].centers.size(), 1u);
  const auto box = mesh.bounds();
  // Level 0: centred on the bounds, edge = largest extent * (1 + 1e-9) (a few ulps).
  EXPECT_LE((tree.levels[0].centers[0] - box.center()).norm(), 1e-12 * tree.levels[0].edge);
  EXPECT_NEAR(tree.levels[0].edge, box.sizes().maxCoeff() * (1 + 1e-9),
              1e-15 * tree.levels[0].edge);
  for (int k = 0; k <= leafLevel; ++k) {
    const SphereTreeLevel& L = tree.levels[k];
    EXPECT_EQ(L.edge, std::ldexp(tree.levels[0].edge, -k));  // halving is exact in binary
    EXPECT_NEAR(L.radius, L.edge * std::sqrt(3.0) / 2, 1e-15 * L.edge);
    ASSERT_EQ(L.childBegin.size(), L.centers.size() + 1);
    if (k == leafLevel) {
      for (auto b : L.childBegin) EXPECT_EQ(b, 0u);
      continue;
    }
    const SphereTreeLevel& next = tree.levels[k + 1];
    EXPECT_EQ(L.childBegin.front(), 0u);
    EXPECT_EQ(L.childBegin.back(), next.centers.size());
    for (std::size_t i = 0; i < L.centers.size(); ++i) {
      const auto begin = L.childBegin[i], end = L.childBegin[i + 1];
      // A surface voxel always has a surface child (a triangle in the parent is in a child),
      // and at most 8.
      EXPECT_LT(begin, end);
      EXPECT_LE(end - begin, 8u);
      Vec3 previous = Vec3::Constant(-INFINITY);
      for (auto j = begin; j < end; ++j) {
        // A child's centre is at parent centre +- a_{k+1}/2 on each axis, i.e. the child cube
        // lies inside the parent cube (round-off: a few ulps of the coordinates).
        const Vec3 d = next.centers[j] - L.centers[i];
        for (int a = 0; a < 3; ++a) EXPECT_NEAR(std::abs(d[a]), next.edge / 2, 1e-12 * L.edge);
        // Fixed (z, y, x) order: strictly increasing in (z, y, x) lexicographic order.
        const Vec3& c = next.centers[j];
        EXPECT_TRUE(std::tie(previous.z(), previous.y(), previous.x()) <
                    std::tie(c.z(), c.y(), c.x()));
        previous = c;
      }
    }
  }
  // The bounding sphere encloses every leaf sphere and is the smallest origin-centred one.
  double farthest = 0;
  for (const Vec3& c : tree.leaves().centers) {
    EXPECT_LE(c.norm() + tree.leaves().radius, tree.boundingRadius);
    farthest = std::max(farthest, c.norm() + tree.leaves().radius);
  }
  EXPECT_EQ(tree.boundingRadius, farthest);
}

// Every leaf is overlapped by a triangle, and (brute force over the full 8^k grid) every voxel
// that any triangle overlaps is a leaf: the tree holds exactly the surface voxels.
void expectExactlySurfaceVoxels(const SphereTree& tree, const TriMesh& mesh) {
  const SphereTreeLevel& leaves = tree.leaves();
  const int n = 1 << tree.leafLevel();
  const Vec3 origin = tree.levels[0].centers[0] - Vec3::Constant(tree.levels[0].edge / 2);
  const Vec3 half = Vec3::Constant(leaves.edge / 2);
  std::set<std::array<long, 3>> inTree;
  for (const Vec3& c : leaves.centers) {
    const Vec3 g = (c - origin) / leaves.edge - Vec3::Constant(0.5);  // integer grid coords
    inTree.insert({std::lround(g.x()), std::lround(g.y()), std::lround(g.z())});
  }
  EXPECT_EQ(inTree.size(), leaves.centers.size());  // no duplicate voxel
  std::size_t surface = 0;
  for (int z = 0; z < n; ++z)
    for (int y = 0; y < n; ++y)
      for (int x = 0; x < n; ++x) {
        const Vec3 c = origin + leaves.edge * Vec3(x + 0.5, y + 0.5, z + 0.5);
        bool hit = false;
        for (const auto& t : mesh.triangles) {
          if (triangleBoxOverlap(c, half, mesh.vertices[t[0]], mesh.vertices[t[1]],
                                 mesh.vertices[t[2]])) {
            hit = true;
            break;
          }
        }
        surface += hit;
        EXPECT_EQ(inTree.count({x, y, z}) == 1, hit) << x << " " << y << " " << z;
      }
  EXPECT_EQ(surface, leaves.centers.size());
}

TEST(SphereTree, CubeFillingTheRootHasClosedFormCounts) {
  // The root cube is the mesh cube enlarged by 1e-9, so at level k (n = 2^k per axis) the
  // surface voxels are exactly the outer shell: n^3 - (n - 2)^3.
  const TriMesh cube = test::boxMesh(Vec3(-1, -1, -1), Vec3(1, 1, 1));
  const SphereTree tree = buildSphereTree(cube, 4);
  expectWellFormed(tree, cube, 4);
  for (int k = 1; k <= 4; ++k) {
    const std::size_t n = std::size_t(1) << k;
    EXPECT_EQ(tree.levels[k].centers.size(), n * n * n - (n - 2) * (n - 2) * (n - 2)) << k;
  }
}

TEST(SphereTree, ExactSurfaceVoxelsOfSeveralMeshes) {
  TriMesh rotated = test::boxMesh(Vec3(-1, -0.5, -0.3), Vec3(1, 0.5, 0.3));
  const Mat3 R = Eigen::AngleAxisd(0.9, Vec3(1, -2, 0.5).normalized()).toRotationMatrix();
  for (Vec3& v : rotated.vertices) v = R * v;
  const TriMesh meshes[] = {
      test::icosphere(2, 1.0), rotated,
      test::extrudedPolygon({{1, 1}, {1, 3}, {0, 3}, {0, 0}, {2, 0}, {2, 1}}, 0, 0.7)};
  for (const TriMesh& m : meshes) {
    for (int level : {1, 3, 4}) {
      const SphereTree tree = buildSphereTree(m, level);
      expectWellFormed(tree, m, level);
      expectExactlySurfaceVoxels(tree, m);
    }
  }
}

TEST(SphereTree, SpotSurfaceSamplesLieInLeafSpheres) {
  const TriMesh spot = centredMesh(importMesh(VOXFALL_TEST_DATA_DIR "/spot.obj"), Vec3(1, 1, 1));
  const SphereTree tree = buildSphereTree(spot, 5);
  expectWellFormed(tree, spot, 5);
  const SphereTreeLevel& leaves = tree.leaves();
  std::size_t uncovered = 0;
  for (const Vec3& p : surfaceSamples(spot)) {
    double best = INFINITY;
    for (const Vec3& c : leaves.centers) best = std::min(best, (p - c).norm());
    // A surface point is in a surface voxel, whose circumscribed sphere holds it; the margin
    // is round-off on O(1) coordinates.
    uncovered += best > leaves.radius * (1 + 1e-12);
    EXPECT_LE(best, leaves.radius * (1 + 1e-12)) << p.transpose();
  }
  EXPECT_EQ(uncovered, 0u);
  // The brute force over the full grid is cheap enough on spot at level 4 (4096 voxels).
  const SphereTree coarse = buildSphereTree(spot, 4);
  expectExactlySurfaceVoxels(coarse, spot);
}

bool sameTree(const SphereTree& a, const SphereTree& b) {
  if (a.levels.size() != b.levels.size() || a.boundingRadius != b.boundingRadius) return false;
  for (std::size_t k = 0; k < a.levels.size(); ++k) {
    const auto &x = a.levels[k], &y = b.levels[k];
    if (x.edge != y.edge || x.radius != y.radius || x.centers != y.centers ||
        x.childBegin != y.childBegin)
      return false;
  }
  return true;
}

TEST(SphereTree, Deterministic) {
  const TriMesh spot = importMesh(VOXFALL_TEST_DATA_DIR "/spot.obj");
  EXPECT_TRUE(sameTree(buildSphereTree(spot, 6), buildSphereTree(spot, 6)));
  // A coarser build is the prefix of a finer one: level k does not depend on the leaf level.
  const SphereTree fine = buildSphereTree(spot, 6), coarse = buildSphereTree(spot, 4);
  for (int k = 0; k < 4; ++k) {
    EXPECT_EQ(coarse.levels[k].centers, fine.levels[k].centers);
    EXPECT_EQ(coarse.levels[k].childBegin, fine.levels[k].childBegin);
  }
  EXPECT_EQ(coarse.levels[4].centers, fine.levels[4].centers);
}

}  // namespace
}  // namespace vf

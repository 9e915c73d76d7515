// MeshBvh and the diagnostics built on it against the brute-force references, which stay in
// sim/geometry/mesh_query.h (all-triangle distance and generalised winding number):
//   - nearest distance equals the all-triangle distance, inside equals the winding number,
//     on random points around closed meshes of the paper's scenes (non-convex ones included);
//   - nearest(p, enough), which may stop early, is exact beyond `enough`;
//   - meshPenetration (BVH) equals a brute-force penetration written here, on random poses of
//     two overlapping bodies, also when given the deepest so far.
#include "sim/geometry/mesh_bvh.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <string>

#include "sim/collide/penetration.h"
#include "sim/core/prng.h"
#include "sim/geometry/mesh_checks.h"
#include "sim/geometry/mesh_import.h"
#include "sim/geometry/mesh_query.h"
#include "sim/shape/shape.h"

namespace vf {
namespace {

TriMesh sceneMesh(const std::string& name) {
  return importMesh(std::string(VOXFALL_SOURCE_DIR) + "/scenes/meshes/" + name);
}

// Both distances are exact up to rounding of O(1) coordinates: 1e-12 m covers it. The inside
// decision is compared only away from the surface (1e-9 m), where neither flips on round-off.
constexpr double kRoundOff = 1e-12;
constexpr double kNearSurface = 1e-9;

class MeshBvhOnSceneMeshes : public ::testing::TestWithParam<const char*> {};

TEST_P(MeshBvhOnSceneMeshes, NearestAndInsideEqualBruteForce) {
  const TriMesh mesh = sceneMesh(GetParam());
  const MeshBvh bvh(mesh);
  const auto box = mesh.bounds();
  const Vec3 margin = 0.2 * box.sizes();
  Prng rng(11);
  int inside = 0, compared = 0;
  for (int i = 0; i < 3000; ++i) {
    Vec3 p;
    for (int k = 0; k < 3; ++k)
      p[k] = rng.uniform(box.min()[k] - margin[k], box.max()[k] + margin[k]);
    const double d = distanceToMesh(mesh, p);
    const MeshBvh::Nearest n = bvh.nearest(p);
    EXPECT_NEAR(n.distance, d, kRoundOff) << p.transpose();
    EXPECT_NEAR((n.point - p).norm(), d, kRoundOff) << p.transpose();
    if (d < kNearSurface) continue;
    EXPECT_EQ(n.inside, pointInsideMesh(mesh, p)) << p.transpose();
    inside += n.inside;
    ++compared;
  }
  EXPECT_GT(inside, 100) << "the points cover both outcomes";
  EXPECT_LT(inside, compared - 100);
}

// Points exactly on vertices' and edges' normals, where the nearest feature is a vertex or an
// edge: the pseudonormal cases (a face normal alone would misjudge these on non-convex edges).
TEST_P(MeshBvhOnSceneMeshes, FeaturePointsOffVerticesAndEdges) {
  const TriMesh mesh = sceneMesh(GetParam());
  const MeshBvh bvh(mesh);
  const double size = mesh.bounds().sizes().maxCoeff();
  Prng rng(5);
  for (const auto& t : mesh.triangles)
    for (int k = 0; k < 3; ++k) {
      const Vec3& a = mesh.vertices[t[k]];
      const Vec3& b = mesh.vertices[t[(k + 1) % 3]];
      for (const Vec3& base : {a, Vec3(0.5 * (a + b))}) {
        Vec3 dir(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1));
        const Vec3 p = base + 0.01 * size * dir.normalized();
        if (distanceToMesh(mesh, p) < kNearSurface) continue;
        EXPECT_EQ(bvh.nearest(p).inside, pointInsideMesh(mesh, p)) << p.transpose();
      }
    }
}

// The early stop of nearest(p, enough): a result beyond `enough` is the full search's, bit
// for bit; one within it is a surface point that near (so it may not be the nearest).
TEST_P(MeshBvhOnSceneMeshes, SearchStoppedWithinEnoughIsExactBeyondIt) {
  const TriMesh mesh = sceneMesh(GetParam());
  const MeshBvh bvh(mesh);
  const auto box = mesh.bounds();
  const double size = box.sizes().maxCoeff();
  Prng rng(17);
  int stopped = 0, beyond = 0;
  for (int i = 0; i < 2000; ++i) {
    Vec3 p;
    for (int k = 0; k < 3; ++k) p[k] = rng.uniform(box.min()[k], box.max()[k]);
    const double enough = rng.uniform(0, 0.3 * size);
    const MeshBvh::Nearest full = bvh.nearest(p), quick = bvh.nearest(p, enough);
    if (quick.distance > enough) {
      EXPECT_EQ(quick.distance, full.distance) << p.transpose();
      EXPECT_EQ(quick.point, full.point) << p.transpose();
      EXPECT_EQ(quick.inside, full.inside) << p.transpose();
      ++beyond;
    } else {
      EXPECT_LE(full.distance, quick.distance);
      EXPECT_NEAR((quick.point - p).norm(), quick.distance, kRoundOff);
      EXPECT_LT(distanceToMesh(mesh, quick.point), kRoundOff) << "a point of the surface";
      stopped += quick.distance > full.distance;  // stopped before the nearest
    }
  }
  EXPECT_GT(beyond, 100) << "both outcomes are exercised";
  EXPECT_GT(stopped, 10) << "the search really stops early";
}

INSTANTIATE_TEST_SUITE_P(Meshes, MeshBvhOnSceneMeshes,
                         ::testing::Values("cross.obj", "barrel.obj", "highpoly_block.obj",
                                           "rock.obj", "stack_block.obj"));

// The brute-force penetration: every surface sample of A tested against all of B's triangles.
double bruteForcePenetration(const Shape& a, const Pose& pa, const Shape& b, const Pose& pb) {
  double deepest = 0;
  for (const Vec3& s : surfaceSamples(a.mesh)) {
    const Vec3 inB = pb.q.conjugate() * (pa.x + pa.q * s - pb.x);
    if (pointInsideMesh(b.mesh, inB)) deepest = std::max(deepest, distanceToMesh(b.mesh, inB));
  }
  return deepest;
}

TEST(MeshPenetration, EqualsBruteForceOnRandomPoses) {
  const auto cross = makeShape("cross", sceneMesh("cross.obj"), Vec3::Ones(), 800, 2);
  const auto barrel = makeShape("barrel", sceneMesh("barrel.obj"), Vec3::Ones(), 800, 2);
  Prng rng(3);
  int overlapping = 0;
  for (int i = 0; i < 60; ++i) {
    const Shape& a = *cross;
    const Shape& b = i % 2 ? *cross : *barrel;
    auto randomQuat = [&] {
      Quat q(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1));
      return q.normalized();
    };
    const Pose pa{Vec3::Zero(), randomQuat()};
    const Vec3 offset(rng.uniform(-0.3, 0.3), rng.uniform(-0.3, 0.3), rng.uniform(-0.3, 0.3));
    const Pose pb{offset, randomQuat()};
    const double fast = meshPenetration(a, pa, b, pb);
    EXPECT_NEAR(fast, bruteForcePenetration(a, pa, b, pb), kRoundOff) << "pose " << i;
    EXPECT_NEAR(meshPenetration(b, pb, a, pa), bruteForcePenetration(b, pb, a, pa), kRoundOff);
    overlapping += fast > 0;
    // With a running maximum (as the diagnostics pass it): the larger of the two.
    for (const double atLeast : {0.5 * fast, fast, 2 * fast + 0.01}) {
      EXPECT_EQ(meshPenetration(a, pa, b, pb, atLeast), std::max(fast, atLeast)) << "pose " << i;
    }
  }
  EXPECT_GT(overlapping, 20) << "the poses really overlap";
}

}  // namespace
}  // namespace vf

// pointInsideMesh, distanceToMesh and surfaceSamples against closed forms (box) and an
// independent ray-parity inside test (spot.obj).
#include "sim/geometry/mesh_query.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>

#include "sim/core/prng.h"
#include "sim/geometry/mesh_import.h"
#include "tests/sim/test_meshes.h"

namespace vf {
namespace {

// Distance from p to the surface of the axis-aligned box [lo, hi] (closed form).
double boxSurfaceDistance(const Vec3& lo, const Vec3& hi, const Vec3& p) {
  const Vec3 c = (lo + hi) / 2, h = (hi - lo) / 2;
  const Vec3 q = (p - c).cwiseAbs() - h;             // per-axis signed distance to the slab faces
  if ((q.array() <= 0).all()) return -q.maxCoeff();  // inside: nearest face
  return q.cwiseMax(0.0).norm();                     // outside: nearest point of the box
}

TEST(MeshQuery, BoxInsideOutsideAndDistance) {
  const Vec3 lo(-1, 0, 2), hi(3, 1, 2.5);
  const TriMesh box = test::boxMesh(lo, hi);
  Prng rng(42);
  int inside = 0;
  for (int i = 0; i < 2000; ++i) {
    const Vec3 p(rng.uniform(-2, 4), rng.uniform(-0.5, 1.5), rng.uniform(1.5, 3));
    const double d = boxSurfaceDistance(lo, hi, p);
    // Both are O(1) computations on O(1) values: 1e-12 absolute covers the round-off.
    EXPECT_NEAR(distanceToMesh(box, p), d, 1e-12) << p.transpose();
    const bool in = ((p - lo).array() > 0).all() && ((hi - p).array() > 0).all();
    if (d > 1e-9) {  // the winding number is only decided away from the surface
      EXPECT_EQ(pointInsideMesh(box, p), in) << p.transpose();
    }
    inside += in;
  }
  EXPECT_GT(inside, 100);  // the sample really covers both cases (expected ~220)
  EXPECT_LT(inside, 1900);
  EXPECT_TRUE(pointInsideMesh(box, Vec3(1, 0.5, 2.25)));
  EXPECT_TRUE(pointInsideMesh(box, Vec3(2.999, 0.5, 2.25)));
  EXPECT_FALSE(pointInsideMesh(box, Vec3(3.001, 0.5, 2.25)));
  EXPECT_FALSE(pointInsideMesh(box, Vec3(100, 100, 100)));
}

// Ray-parity oracle: count crossings of the ray p + t d (t > 0) with the triangles (solve
// p + t d = a + u (b - a) + v (c - a) by Cramer's rule). Odd = inside. A fixed, irrational-
// looking direction makes grazing hits of edges and vertices practically impossible.
bool insideByRayParity(const TriMesh& m, const Vec3& p) {
  const Vec3 d = Vec3(0.5383, 0.2976, 0.7891).normalized();
  int crossings = 0;
  for (const auto& t : m.triangles) {
    const Vec3 &a = m.vertices[t[0]], &b = m.vertices[t[1]], &c = m.vertices[t[2]];
    const Vec3 e1 = b - a, e2 = c - a, s = p - a;
    Mat3 M;
    M << -d, e1, e2;  // [-d e1 e2] (t u v)^T = s
    const double det = M.determinant();
    if (det == 0) continue;
    const Vec3 tuv = M.inverse() * s;
    if (tuv[0] > 0 && tuv[1] >= 0 && tuv[2] >= 0 && tuv[1] + tuv[2] <= 1) ++crossings;
  }
  return crossings % 2 == 1;
}

TEST(MeshQuery, SpotInsideMatchesRayParity) {
  const TriMesh spot = importMesh(VOXFALL_TEST_DATA_DIR "/spot.obj");
  const auto b = spot.bounds();
  Prng rng(7);
  int tested = 0, inside = 0;
  for (int i = 0; i < 300; ++i) {
    Vec3 p;
    for (int k = 0; k < 3; ++k) p[k] = rng.uniform(b.min()[k], b.max()[k]);
    // Skip points within 1e-6 of the surface, where either test may flip on round-off.
    if (distanceToMesh(spot, p) < 1e-6) continue;
    const bool in = insideByRayParity(spot, p);
    EXPECT_EQ(pointInsideMesh(spot, p), in) << p.transpose();
    ++tested;
    inside += in;
  }
  EXPECT_GT(tested, 250);
  EXPECT_GT(inside, 20);  // both outcomes occur
  EXPECT_LT(inside, tested - 20);
}

TEST(MeshQuery, SurfaceSamplesOfBox) {
  const TriMesh box = test::boxMesh(Vec3(0, 0, 0), Vec3(1, 2, 3));
  const auto samples = surfaceSamples(box);
  // 8 vertices + 18 edges (12 box edges + 6 face diagonals) + 12 centroids.
  EXPECT_EQ(samples.size(), 8u + 18u + 12u);
  std::set<std::array<double, 3>> unique;
  for (const Vec3& s : samples) {
    EXPECT_LE(boxSurfaceDistance(Vec3(0, 0, 0), Vec3(1, 2, 3), s), 1e-15) << s.transpose();
    unique.insert({s.x(), s.y(), s.z()});
  }
  EXPECT_EQ(unique.size(), samples.size());  // no edge midpoint repeated
  EXPECT_EQ(surfaceSamples(box), samples);   // deterministic order
}

// Clusters hold every point once, each within its cluster's sphere, and a cluster is one cell
// of the grid: points of different clusters never share a cell.
TEST(MeshQuery, SampleClustersPartitionThePointsIntoCellSpheres) {
  Prng rng(8);
  // Two corners fix the bounds to [-1, 3] x [0, 1] x [5, 5.5], so the cells are exactly 1 m.
  std::vector<Vec3> points{Vec3(-1, 0, 5), Vec3(3, 1, 5.5)};
  for (int i = 0; i < 500; ++i)
    points.emplace_back(rng.uniform(-1, 3), rng.uniform(0, 1), rng.uniform(5, 5.5));
  const SampleClusters c = clusterSamples(points, 4);
  ASSERT_EQ(c.points.size(), points.size());
  std::multiset<std::array<double, 3>> given, grouped;
  for (const Vec3& p : points) given.insert({p.x(), p.y(), p.z()});
  for (const Vec3& p : c.points) grouped.insert({p.x(), p.y(), p.z()});
  EXPECT_EQ(grouped, given);
  // 4 cells along x, 1 m: one along y and one along z.
  EXPECT_EQ(c.clusters.size(), 4u);
  std::uint32_t next = 0;
  for (const SampleClusters::Cluster& k : c.clusters) {
    EXPECT_EQ(k.begin, next);
    EXPECT_LT(k.begin, k.end);
    next = k.end;
    for (std::uint32_t i = k.begin; i < k.end; ++i) {
      EXPECT_LE((c.points[i] - k.centre).norm(), k.radius);
      // x decides the cell here; every point of a cluster in the same 1 m slab.
      auto slab = [](const Vec3& p) { return std::min(std::floor(p.x() + 1), 3.0); };
      EXPECT_EQ(slab(c.points[i]), slab(c.points[k.begin]));
    }
  }
  EXPECT_EQ(next, points.size());
  EXPECT_TRUE(clusterSamples({}, 4).clusters.empty());
  // Chosen from the count: round(sqrt(502 / 24)) = 5 cells of 0.8 m along x, so 2 along y and
  // 1 along z, all holding points; a box's 38 samples make one.
  EXPECT_EQ(clusterSamples(points).clusters.size(), 10u);
  EXPECT_EQ(
      clusterSamples(surfaceSamples(test::boxMesh(Vec3(0, 0, 0), Vec3(1, 2, 3)))).clusters.size(),
      1u);
}

}  // namespace
}  // namespace vf

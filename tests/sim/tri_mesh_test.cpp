// TriMesh: bounds, scale (with winding flip for reflections) and translate.
#include "sim/geometry/tri_mesh.h"

#include <gtest/gtest.h>

#include "tests/sim/test_meshes.h"

namespace vf {
namespace {

TEST(TriMesh, BoundsOfBox) {
  const TriMesh m = test::boxMesh(Vec3(-1, 2, 3), Vec3(4, 5, 9));
  const auto b = m.bounds();
  // Bounds are a min/max of stored coordinates: exact.
  EXPECT_EQ(b.min(), Vec3(-1, 2, 3));
  EXPECT_EQ(b.max(), Vec3(4, 5, 9));
  EXPECT_TRUE(TriMesh{}.bounds().isEmpty());
}

TEST(TriMesh, ScaleMultipliesCoordinatesAndKeepsOutwardOrientation) {
  const TriMesh original = test::boxMesh(Vec3(0, 0, 0), Vec3(1, 2, 3));
  for (const Vec3& f : {Vec3(2, 3, 4), Vec3(-2, 3, 4), Vec3(-2, -3, 4), Vec3(-2, -3, -4)}) {
    TriMesh m = original;
    m.scale(f);
    for (std::size_t i = 0; i < m.vertices.size(); ++i)
      EXPECT_EQ(m.vertices[i], original.vertices[i].cwiseProduct(f));  // one exact product
    // The flux volume is positive only for outward triangles: it must be 6 |f1 f2 f3|
    // whatever the signs (1e-12: a dozen products of small integers, round-off ~1e-15).
    EXPECT_NEAR(test::fluxVolume(m), 6 * std::abs(f.prod()), 1e-12) << f.transpose();
  }
}

TEST(TriMesh, TranslateMovesEveryVertex) {
  TriMesh m = test::boxMesh(Vec3(0, 0, 0), Vec3(1, 1, 1));
  m.translate(Vec3(0.5, -2, 10));
  EXPECT_EQ(m.bounds().min(), Vec3(0.5, -2, 10));
  EXPECT_EQ(m.bounds().max(), Vec3(1.5, -1, 11));  // all sums exact in binary
}

}  // namespace
}  // namespace vf

// makeShape and centredMesh: scaling, centring, mass properties with density, body-frame
// quantities (meshOrigin, diameter, inverse inertia) and the sphere tree it builds or reuses.
#include "sim/shape/shape.h"

#include <gtest/gtest.h>

#include <cmath>

#include "sim/geometry/mass_properties.h"
#include "tests/sim/test_meshes.h"

namespace vf {
namespace {

TEST(Shape, CentredMeshScalesThenMovesComToOrigin) {
  const TriMesh box = test::boxMesh(Vec3(1, 2, 3), Vec3(2, 4, 7));  // COM (1.5, 3, 5)
  const Vec3 scale(2, -1, 0.5);                                     // a reflection
  const TriMesh m = centredMesh(box, scale);
  // Scaled extents 2 x 2 x 2, centred: bounds [-1, 1]^3 (round-off of O(1) values).
  EXPECT_LE((m.bounds().min() - Vec3(-1, -1, -1)).norm(), 1e-12);
  EXPECT_LE((m.bounds().max() - Vec3(1, 1, 1)).norm(), 1e-12);
  const auto mp = computeMassProperties(m, 1.0);
  EXPECT_LE(mp.centerOfMass.norm(), 1e-12);
  EXPECT_NEAR(mp.volume, 8, 1e-12);  // positive: the winding was flipped with the reflection
}

TEST(Shape, MakeShapeOfOffCentreBox) {
  const double rho = 800;
  const TriMesh box = test::boxMesh(Vec3(1, 2, 3), Vec3(2, 4, 7));
  const Vec3 scale(0.5, 0.5, 0.5);  // -> 0.5 x 1 x 2, COM at (0.75, 1.5, 2.5)
  const auto shape = makeShape("box", box, scale, rho, 3);
  const double a = 0.5, b = 1, c = 2, m = rho * a * b * c;
  // Sums of a dozen O(1) terms: 1e-12 relative.
  EXPECT_EQ(shape->name, "box");
  EXPECT_NEAR(shape->volume, a * b * c, 1e-12);
  EXPECT_NEAR(shape->mass, m, 1e-12 * m);
  EXPECT_LE((shape->meshOrigin - Vec3(-0.75, -1.5, -2.5)).norm(), 1e-12);
  const Mat3 want = Vec3(b * b + c * c, a * a + c * c, a * a + b * b).asDiagonal() * (m / 12);
  EXPECT_LE((shape->inertiaBody - want).norm(), 1e-12 * want.norm());
  EXPECT_LE((shape->inertiaBody * shape->inertiaBodyInv - Mat3::Identity()).norm(), 1e-12);
  // The body frame mesh is centred; the file origin maps to meshOrigin.
  EXPECT_LE((shape->mesh.bounds().center()).norm(), 1e-12);
  EXPECT_LE((shape->mesh.vertices[0] - (box.vertices[0] * 0.5 + shape->meshOrigin)).norm(), 1e-12);
  // Diameter: the box diagonal (every corner is at half the diagonal from the centre).
  EXPECT_NEAR(shape->diameter, std::sqrt(a * a + b * b + c * c), 1e-12);
  ASSERT_NE(shape->tree, nullptr);
  EXPECT_EQ(shape->tree->leafLevel(), 3);
}

TEST(Shape, TreeIsTheTreeOfCentredMeshAndCanBeShared) {
  const TriMesh l = test::extrudedPolygon({{1, 1}, {1, 3}, {0, 3}, {0, 0}, {2, 0}, {2, 1}}, 0, 1);
  const Vec3 scale(1.5, 1.5, 1.5);
  const auto a = makeShape("l", l, scale, 800, 4);
  // centredMesh gives the very mesh makeShape uses, bit for bit, whatever the density...
  const TriMesh key = centredMesh(l, scale);
  EXPECT_EQ(a->mesh.vertices, key.vertices);
  EXPECT_EQ(a->mesh.triangles, key.triangles);
  // ...so a tree built from it is identical to the one makeShape builds.
  const auto tree = std::make_shared<const SphereTree>(buildSphereTree(key, 4));
  EXPECT_EQ(tree->leaves().centers, a->tree->leaves().centers);
  EXPECT_EQ(tree->boundingRadius, a->tree->boundingRadius);
  // A given tree is used as is (shared, not rebuilt), here by a shape of another density.
  const auto b = makeShape("l-heavy", l, scale, 2500, 4, tree);
  EXPECT_EQ(b->tree, tree);
  EXPECT_NEAR(b->mass / a->mass, 2500.0 / 800.0, 1e-12);
  // The tree's bounding sphere encloses the whole mesh (every vertex is in a leaf sphere).
  EXPECT_GE(a->tree->boundingRadius, a->diameter / 2);
}

}  // namespace
}  // namespace vf

// The polygon collider (the paper's comparison method) on cases whose contacts are known by
// hand: a face resting on a face (4 corners), two edges crossing (1 contact at the closest
// points), a box dropped on the floor (rebound to eps^2 of its height), separated bodies (no
// contact), non-convex meshes refused, and a cost that grows with the polygon count.
#include "sim/collide/polygon_contact.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "sim/collide/narrow_phase.h"
#include "sim/core/error.h"
#include "sim/geometry/mesh_import.h"
#include "sim/scene/scene.h"
#include "sim/shape/convex_polyhedron.h"
#include "tests/support/test_world.h"

namespace vf {
namespace {

constexpr double kG = 9.81;

ConvexPolyhedron boxPolyhedron(double a, double b, double c) {
  return buildConvexPolyhedron(test::boxMesh(a, b, c), "box", "test");
}

Quat about(const Vec3& axis, double degrees) {
  return Quat(Eigen::AngleAxisd(degrees * std::numbers::pi / 180, axis.normalized()));
}

TEST(PolygonContact, BoxFacesDownOnABoxGivesItsFourCornersWithTheFaceNormal) {
  // A 0.3 m cube turned 30 degrees about z lies on a 1 x 1 x 0.2 m slab whose top is z = 0.1,
  // sunk 1 mm into it. Oracle: its four bottom corners, pushed up along +z, 1 mm deep.
  const ConvexPolyhedron cube = boxPolyhedron(0.3, 0.3, 0.3), slab = boxPolyhedron(1, 1, 0.2);
  const double depth = 1e-3, top = 0.1;
  const Quat q = about(Vec3::UnitZ(), 30);
  const Vec3 x(0.05, -0.02, top + 0.15 - depth);
  std::vector<Contact> out;
  collide(polygonCollider(0, cube, x, q), polygonCollider(1, slab, Vec3::Zero(), Quat::Identity()),
          out);
  ASSERT_EQ(out.size(), 4u);
  for (double sx : {-1.0, 1.0})
    for (double sy : {-1.0, 1.0}) {
      const Vec3 corner = x + q * Vec3(0.15 * sx, 0.15 * sy, -0.15);
      // The contact point lies midway between the corner and the slab's top.
      const Vec3 expected(corner.x(), corner.y(), top - depth / 2);
      const auto hit = std::find_if(out.begin(), out.end(), [&](const Contact& c) {
        return (c.point - expected).norm() < 1e-12;
      });
      ASSERT_NE(hit, out.end()) << "corner " << sx << ", " << sy;
      EXPECT_LT((hit->normal - Vec3::UnitZ()).norm(), 1e-12);
      EXPECT_NEAR(hit->depth, depth, 1e-12);
      EXPECT_EQ(hit->a, 0);
      EXPECT_EQ(hit->b, 1);
    }
  // Swapping the bodies flips the normal and keeps the points.
  std::vector<Contact> swapped;
  collide(polygonCollider(1, slab, Vec3::Zero(), Quat::Identity()), polygonCollider(0, cube, x, q),
          swapped);
  ASSERT_EQ(swapped.size(), 4u);
  for (const Contact& c : swapped) EXPECT_LT((c.normal + Vec3::UnitZ()).norm(), 1e-12);
}

TEST(PolygonContact, TwoBoxesCrossingEdgeToEdgeGiveOneContactAtTheClosestPoints) {
  // B: a box turned 45 degrees about x, so its top is an edge along x at height h = 0.1 sqrt 2
  // (a 0.2 x 0.2 cross-section). A: a box turned 45 degrees about y, its bottom an edge along
  // y, lowered 2 mm through B's edge and shifted so the edges cross at (0.05, 0).
  const ConvexPolyhedron a = boxPolyhedron(0.2, 0.6, 0.2), b = boxPolyhedron(0.6, 0.2, 0.2);
  const double h = 0.1 * std::sqrt(2.0), overlap = 2e-3;
  const Vec3 xa(0.05, 0.04, 2 * h - overlap);
  std::vector<Contact> out;
  collide(polygonCollider(0, a, xa, about(Vec3::UnitY(), 45)),
          polygonCollider(1, b, Vec3::Zero(), about(Vec3::UnitX(), 45)), out);
  ASSERT_EQ(out.size(), 1u);
  // Closest points: (0.05, 0, h - overlap) on A's edge, (0.05, 0, h) on B's; the contact lies
  // midway, pushing A up.
  EXPECT_LT((out[0].point - Vec3(0.05, 0, h - overlap / 2)).norm(), 1e-12);
  EXPECT_LT((out[0].normal - Vec3::UnitZ()).norm(), 1e-12);
  EXPECT_NEAR(out[0].depth, overlap, 1e-12);
}

TEST(PolygonContact, SeparatedBodiesHaveNoContact) {
  // The same crossing edges, 1 cm apart (the margin is 1e-3 of a 0.33 m bounding radius).
  const ConvexPolyhedron a = boxPolyhedron(0.2, 0.6, 0.2), b = boxPolyhedron(0.6, 0.2, 0.2);
  const double h = 0.1 * std::sqrt(2.0);
  std::vector<Contact> out;
  collide(polygonCollider(0, a, Vec3(0.05, 0.04, 2 * h + 0.01), about(Vec3::UnitY(), 45)),
          polygonCollider(1, b, Vec3::Zero(), about(Vec3::UnitX(), 45)), out);
  EXPECT_TRUE(out.empty());
}

TEST(PolygonContact, VerticesUnderTheFloorAreContacts) {
  const ConvexPolyhedron cube = boxPolyhedron(0.3, 0.3, 0.3);
  // Tilted 10 degrees about x and sunk so that its lowest edge is 2 mm under z = 0: the two
  // vertices of that edge touch, nothing else.
  const Quat q = about(Vec3::UnitX(), 10);
  double lowest = INFINITY;
  for (const Vec3& v : cube.vertices) lowest = std::min(lowest, (q * v).z());
  const Vec3 x(0, 0, -lowest - 2e-3);
  std::vector<Contact> out;
  collide(polygonCollider(0, cube, x, q), planeCollider(0.0), out);
  ASSERT_EQ(out.size(), 2u);
  for (const Contact& c : out) {
    EXPECT_NEAR(c.depth, 2e-3, 1e-12);
    EXPECT_EQ(c.point.z(), 0.0);
    EXPECT_EQ(c.normal, Vec3::UnitZ());
  }
}

// Same box, same drop, same step as the voxel method's scenario test (analytic_test.cpp), with
// the polygon collider: the rebound reaches eps^2 of the drop height.
TEST(PolygonContact, BoxDroppedOnTheFloorReboundsToEpsSquaredOfItsHeight) {
  const double eps = 0.3, h = 0.5, dt = 1e-3, c = 0.2;
  WorldDef def;
  def.groundHeight = 0.0;
  def.contact.restitutionBodyGround = eps;
  def.step = StepRule::fixed(dt);
  World world(def);
  auto box = std::make_shared<Shape>(*test::boxShape(0.3, 0.3, c, 800, 2));
  box->polyhedron = std::make_shared<const ConvexPolyhedron>(boxPolyhedron(0.3, 0.3, c));
  const double zTouch = c / 2;  // centre height when the faces touch
  BodyDef b;
  b.shape = box;
  b.position = Vec3(0, 0, zTouch + h);
  world.addBody(b);
  const test::Rebound r = test::dropAndWatchRebound(world, zTouch, dt, 0.7);
  ASSERT_TRUE(r.bounced);
  const double vBefore = r.vBefore, vAfter = r.vAfter, apex = r.apex;
  // The impact step adds g dt before the impulse: v+ = -eps (v- - g dt) for a flat landing.
  EXPECT_NEAR(vAfter / -vBefore, eps, eps * kG * dt / -vBefore + 1e-9);
  // The four corners are solved one after another (finitely many passes), so the landing
  // leaves a residual tilt; flat means the corners stay level to within the contact margin
  // (rotation angle = 2 |q.vec|, corners 0.15 m from the axis).
  const double margin = kPolygonContactMargin * box->polyhedron->boundingRadius;
  EXPECT_LT(2 * world.state(0).q.vec().norm() * 0.15 * std::sqrt(2.0), margin);
  // Rebound height: Euler on the fall and on the rise (v dt / 2 each) and the travel past
  // first touch before the impulse (< v dt), plus the contact margin (1e-3 of the bounding
  // radius) within which the corners count as touching.
  const double vImpact = std::sqrt(2 * kG * h);
  EXPECT_NEAR(apex, eps * eps * h, 2 * vImpact * dt + margin);
}

TEST(PolygonContact, FlatFacesOfAGriddedBlockAreMergedIntoSix) {
  const TriMesh m = importMesh(test::sourcePath("scenes/meshes/highpoly_block.obj"));
  const ConvexPolyhedron p = buildConvexPolyhedron(m, "block", "test");
  EXPECT_EQ(p.triangles.size(), 192u);
  EXPECT_EQ(p.faces.size(), 6u);
  EXPECT_EQ(p.edges.size(), 3 * 192u / 2);
}

TEST(PolygonContact, CostGrowsWithThePolygonCount) {
  // Two resting pairs in the same pose, 12-triangle boxes and 192-triangle blocks of the same
  // size: the method tests every triangle against every vertex and every edge against every
  // edge, so the feature tests grow about as (triangles)^2.
  const TriMesh high = importMesh(test::sourcePath("scenes/meshes/highpoly_block.obj"));
  const Eigen::AlignedBox3d box = high.bounds();
  const Vec3 size = box.sizes();
  TriMesh centred = high;
  centred.translate(-box.center());
  const ConvexPolyhedron ph = buildConvexPolyhedron(centred, "high", "test");
  const ConvexPolyhedron pl = boxPolyhedron(size.x(), size.y(), size.z());
  const Vec3 above(0.02, 0.01, size.z() - 1e-4);
  std::vector<Contact> lowOut, highOut;
  const std::uint64_t low = collide(polygonCollider(0, pl, above, Quat::Identity()),
                                    polygonCollider(1, pl, Vec3::Zero(), Quat::Identity()), lowOut);
  const std::uint64_t many =
      collide(polygonCollider(0, ph, above, Quat::Identity()),
              polygonCollider(1, ph, Vec3::Zero(), Quat::Identity()), highOut);
  EXPECT_EQ(lowOut.size(), 4u);
  EXPECT_GE(highOut.size(), 4u);  // the outline's corners, plus collinear outline vertices
  EXPECT_GT(many, 100 * low) << low << " vs " << many;
}

TEST(PolygonContact, NonConvexShapeIsRefusedNamingTheShape) {
  SceneSpec spec = loadScene(test::sourcePath("scenes/crosses.toml"));
  spec.collider = ColliderMethod::kPolygon;
  try {
    buildScene(spec);
    FAIL() << "a non-convex cross must be refused";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("crosses.toml:"), std::string::npos) << what;
    EXPECT_NE(what.find("shape 'cross'"), std::string::npos) << what;
    EXPECT_NE(what.find("the polygon method handles convex meshes only; use collider = \"voxel\""),
              std::string::npos)
        << what;
  }
  EXPECT_TRUE(isConvexMesh(test::boxMesh(1, 2, 3)));
}

}  // namespace
}  // namespace vf

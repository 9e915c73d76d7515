// draw_list and camera: World state -> draw data, without GL. Oracles: Eigen's own quaternion
// -> matrix conversion, and the frustum planes written out by hand from the field of view.
#include "render/draw_list.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "render/camera.h"
#include "render_test_util.h"

namespace vf {
namespace {

using test::body;
using test::boxShape;

TEST(DrawList, ModelMatrixIsRotationOfQuaternionAndPosition) {
  const auto shape = boxShape(Vec3(0.5, 0.25, 0.1));
  const Quat q = Quat(0.3, -0.5, 0.7, 0.2).normalized();
  const Vec3 x(1.5, -2.0, 0.75);
  DrawListBuilder builder(CameraSpec{}, 0.0, 16.0 / 9.0);
  const std::vector<BodyView> bodies{body(shape, x, q)};
  const DrawList list = builder.build(bodies);
  ASSERT_EQ(list.instances.size(), 1u);
  const Mat4& m = list.instances[0].model;
  // Exact: the matrix must be built from (x, q) and nothing else (1e-15: one rounding of the
  // quaternion normalisation).
  const Mat3 rotation = m.block<3, 3>(0, 0);
  const Vec3 translation = m.block<3, 1>(0, 3);
  EXPECT_TRUE(rotation.isApprox(q.toRotationMatrix(), 1e-15));
  EXPECT_EQ(translation, x);
  EXPECT_EQ(m.row(3), Eigen::RowVector4d(0, 0, 0, 1));
  // A body-frame vertex lands where the rigid motion puts it.
  const Vec3 v = shape->mesh.vertices[5];
  const Vec4 world = m * Vec4(v.x(), v.y(), v.z(), 1);
  EXPECT_LT((world.head<3>() - (q * v + x)).norm(), 1e-14);
}

TEST(DrawList, BodiesSharingAShapeShareOneMeshAndInactiveBodiesAreNotDrawn) {
  const auto a = boxShape(Vec3(0.5, 0.5, 0.5));
  const auto b = boxShape(Vec3(0.2, 0.2, 0.2));
  std::vector<BodyView> bodies{
      body(a, Vec3(0, 0, 1), Quat::Identity(), 0), body(b, Vec3(1, 0, 1), Quat::Identity(), 1),
      body(a, Vec3(2, 0, 1), Quat::Identity(), 2), body(b, Vec3(3, 0, 1), Quat::Identity(), 3)};
  bodies[3].active = false;
  DrawListBuilder builder(CameraSpec{}, 0.0, 1.0);
  const DrawList list = builder.build(bodies);
  ASSERT_EQ(list.meshes.size(), 2u);
  ASSERT_EQ(list.instances.size(), 3u);
  EXPECT_EQ(list.meshes[0].key, a.get());
  EXPECT_EQ(list.meshes[1].key, b.get());
  EXPECT_EQ(list.instances[0].mesh, 0);
  EXPECT_EQ(list.instances[1].mesh, 1);
  EXPECT_EQ(list.instances[2].mesh, 0);
  EXPECT_EQ(list.instances[2].color, defaultBodyColor(2));
  // The mesh is the shape's own, not a copy.
  EXPECT_EQ(list.meshes[0].mesh.get(), &a->mesh);
}

TEST(DrawList, DefaultPaletteColoursAreDistinct) {
  for (int i = 0; i < 10; ++i) {
    for (int j = i + 1; j < 10; ++j) {
      const Color a = defaultBodyColor(i), b = defaultBodyColor(j);
      const double d = std::abs(a[0] - b[0]) + std::abs(a[1] - b[1]) + std::abs(a[2] - b[2]);
      EXPECT_GT(d, 0.1) << "palette entries " << i << " and " << j << " look alike";
    }
  }
}

// Signed distances of a sphere to the view frustum's six planes, written out from the field
// of view in eye space (looking down -z); all >= 0 means the sphere projects inside the view.
double frustumClearance(const CameraView& c, double aspect, const Vec3& centre, double r) {
  const Vec4 p4 = c.viewMatrix() * Vec4(centre.x(), centre.y(), centre.z(), 1);
  const Vec3 p = p4.head<3>();
  const double b = c.fovYDegrees * std::numbers::pi / 360;  // vertical half angle
  const double a = std::atan(std::tan(b) * aspect);         // horizontal half angle
  const double planes[6] = {
      Vec3(-std::cos(a), 0, -std::sin(a)).dot(p),  // right
      Vec3(std::cos(a), 0, -std::sin(a)).dot(p),   // left
      Vec3(0, -std::cos(b), -std::sin(b)).dot(p),  // top
      Vec3(0, std::cos(b), -std::sin(b)).dot(p),   // bottom
      -p.z() - c.nearPlane,                        // near
      c.farPlane + p.z(),                          // far
  };
  double clearance = planes[0];
  for (double d : planes) clearance = std::min(clearance, d);
  return clearance - r;
}

TEST(DrawList, AutomaticCameraFramesEveryBody) {
  const auto big = boxShape(Vec3(0.5, 0.5, 0.5));
  const auto small = boxShape(Vec3(0.1, 0.3, 0.05));
  std::vector<BodyView> bodies{body(big, Vec3(0, 0, 0.5)), body(small, Vec3(4, -1, 0.05)),
                               body(big, Vec3(-3, 2, 6)), body(small, Vec3(1, 5, 2))};
  for (double aspect : {16.0 / 9.0, 1.0, 9.0 / 16.0, 3.0}) {
    DrawListBuilder builder(CameraSpec{}, 0.0, aspect);
    const DrawList list = builder.build(bodies);
    for (const BodyView& b : bodies) {
      const double r = builder.shapeRadius(b.shape);
      EXPECT_GE(frustumClearance(list.camera, aspect, b.x, r), 0)
          << "aspect " << aspect << ": body at " << b.x.transpose() << " is cut off";
    }
    // And the floor under each body (where it lands and its shadow falls).
    for (const BodyView& b : bodies) {
      EXPECT_GE(frustumClearance(list.camera, aspect, Vec3(b.x.x(), b.x.y(), 0), 0), 0);
    }
    // Not absurdly far: the framed region must fill a good part of the view (the enclosing
    // sphere of these bodies has a radius of about 5 m; 40 degrees vertical field of view).
    EXPECT_LT((list.camera.position - list.camera.lookAt).norm(), 60);
  }
}

TEST(DrawList, AutomaticFramingOnlyGrowsSoEarlierFramesStayInView) {
  const auto shape = boxShape(Vec3(0.5, 0.5, 0.5));
  DrawListBuilder builder(CameraSpec{}, 0.0, 16.0 / 9.0);
  const std::vector<BodyView> early{body(shape, Vec3(10, 10, 5))};
  builder.observe(early);  // simulated, not drawn
  const std::vector<BodyView> now{body(shape, Vec3(0, 0, 0.5))};
  const DrawList list = builder.build(now);
  EXPECT_GE(frustumClearance(list.camera, 16.0 / 9.0, Vec3(10, 10, 5), 0.87), 0);
  EXPECT_GE(frustumClearance(list.camera, 16.0 / 9.0, Vec3(0, 0, 0.5), 0.87), 0);
}

TEST(DrawList, GivenCameraIsUsedAndFollowKeepsItsOffset) {
  CameraSpec spec;
  spec.given = true;
  spec.position = Vec3(1, -8, 3);
  spec.lookAt = Vec3(1, 0, 0.5);
  spec.fovDegrees = 30;
  const auto shape = boxShape(Vec3(0.5, 0.5, 0.5));
  const std::vector<BodyView> bodies{body(shape, Vec3(0, 0, 0.5)), body(shape, Vec3(5, 2, 3))};
  {
    DrawListBuilder builder(spec, 0.0, 1.5);
    const DrawList list = builder.build(bodies);
    EXPECT_EQ(list.camera.position, spec.position);
    EXPECT_EQ(list.camera.lookAt, spec.lookAt);
    EXPECT_EQ(list.camera.fovYDegrees, 30);
  }
  spec.followBody = 1;
  DrawListBuilder builder(spec, 0.0, 1.5);
  const DrawList list = builder.build(bodies);
  EXPECT_EQ(list.camera.lookAt, bodies[1].x);
  EXPECT_LT((list.camera.position - (bodies[1].x + spec.position - spec.lookAt)).norm(), 1e-12);
}

TEST(DrawList, TerrainIsDrawnWithSlopeShadingAndCastsShadows) {
  auto terrain = std::make_shared<TriMesh>();
  terrain->vertices = {Vec3(-5, -5, 0), Vec3(5, -5, 0), Vec3(-5, 5, 2), Vec3(5, 5, 2)};
  terrain->triangles = {{0, 1, 3}, {0, 3, 2}};
  DrawListBuilder builder(CameraSpec{}, std::nullopt, 1.0);
  builder.setTerrain(terrain);
  const std::vector<BodyView> none;
  const DrawList list = builder.build(none);
  ASSERT_EQ(list.instances.size(), 1u);
  EXPECT_EQ(list.instances[0].surface, Surface::terrain);
  EXPECT_TRUE(list.instances[0].castsShadow);
  EXPECT_EQ(list.meshes[0].mesh, terrain);
  // The shadow casters' sphere covers the terrain.
  for (const Vec3& v : terrain->vertices) {
    EXPECT_LE((v - list.casterCentre).norm(), list.casterRadius + 1e-12);
  }
}

TEST(DrawList, SmoothNormalsOfATentBisectTheRidge) {
  // Two 1 m x 1 m slopes meeting at a ridge along y at x = 0: up 45 degrees from the left,
  // down from the right. Ridge vertices get the bisector +z; the eaves their own slope's normal.
  TriMesh tent;
  tent.vertices = {Vec3(-1, 0, 0), Vec3(0, 0, 1), Vec3(1, 0, 0),
                   Vec3(-1, 1, 0), Vec3(0, 1, 1), Vec3(1, 1, 0)};
  tent.triangles = {{0, 1, 4}, {0, 4, 3}, {1, 2, 5}, {1, 5, 4}};
  const std::vector<Vec3> n = smoothVertexNormals(tent);
  ASSERT_EQ(n.size(), 6u);
  const double s = std::sqrt(0.5);
  EXPECT_LT((n[1] - Vec3(0, 0, 1)).norm(), 1e-12);
  EXPECT_LT((n[4] - Vec3(0, 0, 1)).norm(), 1e-12);
  EXPECT_LT((n[0] - Vec3(-s, 0, s)).norm(), 1e-12);
  EXPECT_LT((n[5] - Vec3(s, 0, s)).norm(), 1e-12);
}

TEST(Camera, ShadowProjectionCoversCastersAndTheFloorBelow) {
  const Vec3 sun = Vec3(0.3, -0.5, 0.8).normalized();
  const Vec3 centre(1, 2, 3);
  const double radius = 1.5;
  const ShadowProjection p = fitShadowProjection(sun, centre, radius, 0.0, 2048);
  auto clip = [&](const Vec3& w) -> Vec4 {
    return p.viewProjection * Vec4(w.x(), w.y(), w.z(), 1);
  };
  // Every point of the casters' sphere lies inside the clip box (orthographic: w = 1).
  const std::vector<Vec3> directions{Vec3::UnitX(), -Vec3::UnitX(), Vec3::UnitY(), -Vec3::UnitY(),
                                     Vec3::UnitZ(), -Vec3::UnitZ(), sun,           -sun};
  for (const Vec3& d : directions) {
    const Vec4 c = clip(centre + d * radius);
    EXPECT_LE(c.head<3>().cwiseAbs().maxCoeff(), 1.0) << d.transpose();
  }
  // The floor point in the shadow of the centre projects to the same spot, nearer the far
  // plane than the caster and still inside the depth range.
  const Vec3 floor = centre - sun * (centre.z() / sun.z());
  const Vec4 a = clip(centre), b = clip(floor);
  EXPECT_NEAR(a.x(), b.x(), 1e-9);
  EXPECT_NEAR(a.y(), b.y(), 1e-9);
  EXPECT_GT(b.z(), a.z());
  EXPECT_LT(b.z(), 1.0);
}

TEST(Camera, LookAtMatrixMapsTargetOntoTheNegativeZAxis) {
  const Vec3 eye(4, -6, 3), target(0.5, 0.25, 1);
  const Mat4 v = lookAtMatrix(eye, target, Vec3::UnitZ());
  const Vec4 t = v * Vec4(target.x(), target.y(), target.z(), 1);
  EXPECT_NEAR(t.x(), 0, 1e-12);
  EXPECT_NEAR(t.y(), 0, 1e-12);
  EXPECT_NEAR(t.z(), -(target - eye).norm(), 1e-12);
  // Straight down with up = z still gives a rotation (no NaN).
  const Mat4 down = lookAtMatrix(Vec3(0, 0, 10), Vec3::Zero(), Vec3::UnitZ());
  EXPECT_TRUE(down.allFinite());
  const Mat3 rotation = down.block<3, 3>(0, 0);
  EXPECT_NEAR(rotation.determinant(), 1, 1e-12);
}

}  // namespace
}  // namespace vf

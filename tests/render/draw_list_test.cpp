// draw_list and camera: World state -> draw data, without GL. Oracles: Eigen's own quaternion
// -> matrix conversion, and the frustum planes written out by hand from the field of view.
#include "render/draw_list.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <numbers>

#include "render/camera.h"
#include "render_test_util.h"
#include "sim/scene/scene.h"

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

TEST(DrawList, LargeTerrainIsDrawnAsTilesHoldingEveryTriangleOnceInOrder) {
  // 130 x 130 cells (33,800 triangles, over twice kTerrainTileTriangles) with smooth normals.
  auto terrain = std::make_shared<TriMesh>();
  constexpr int kCells = 130;
  for (int j = 0; j <= kCells; ++j)
    for (int i = 0; i <= kCells; ++i)
      terrain->vertices.push_back(Vec3(0.5 * i, 0.5 * j, std::sin(0.3 * i) * std::cos(0.2 * j)));
  auto at = [](int i, int j) { return static_cast<std::uint32_t>(j * (kCells + 1) + i); };
  for (int j = 0; j < kCells; ++j)
    for (int i = 0; i < kCells; ++i) {
      terrain->triangles.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
      terrain->triangles.push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
    }
  auto normals = std::make_shared<const std::vector<Vec3>>(smoothVertexNormals(*terrain));
  DrawListBuilder builder(CameraSpec{}, std::nullopt, 1.0);
  builder.setTerrain(terrain, normals);
  const DrawList list = builder.build(std::vector<BodyView>{});
  // Each triangle of the whole mesh by its first vertex's position and its index.
  std::map<std::array<double, 3>, std::vector<std::size_t>> byFirst;
  for (std::size_t k = 0; k < terrain->triangles.size(); ++k) {
    const Vec3& p = terrain->vertices[terrain->triangles[k][0]];
    byFirst[{p.x(), p.y(), p.z()}].push_back(k);
  }
  std::vector<int> seen(terrain->triangles.size(), 0);
  std::size_t tiles = 0;
  for (const DrawInstance& inst : list.instances) {
    ASSERT_EQ(inst.surface, Surface::terrain);
    EXPECT_TRUE(inst.castsShadow);
    const DrawMesh& m = list.meshes[static_cast<std::size_t>(inst.mesh)];
    ASSERT_TRUE(m.normals);
    ASSERT_EQ(m.normals->size(), m.mesh->vertices.size());
    EXPECT_LE(m.mesh->triangles.size(), 2 * kTerrainTileTriangles);
    ++tiles;
    std::size_t previous = 0;
    for (const auto& t : m.mesh->triangles) {
      // The whole mesh's triangle with these three vertices (positions and normals equal).
      const Vec3& p = m.mesh->vertices[t[0]];
      std::size_t found = terrain->triangles.size();
      for (const std::size_t k : byFirst[{p.x(), p.y(), p.z()}]) {
        bool same = true;
        for (int c = 0; c < 3; ++c) {
          const std::uint32_t w = terrain->triangles[k][c];
          same = same && terrain->vertices[w] == m.mesh->vertices[t[c]] &&
                 (*normals)[w] == (*m.normals)[t[c]];
        }
        if (same) found = k;
      }
      ASSERT_LT(found, terrain->triangles.size());
      ++seen[found];
      EXPECT_TRUE(previous == 0 || found > previous) << "tile order";
      previous = found;
    }
  }
  EXPECT_GE(tiles, 3u);
  EXPECT_EQ(std::count(seen.begin(), seen.end(), 1), static_cast<long>(seen.size()));
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

// --- cameras for big scenes ------------------------------------------------------------------

// A fixed camera (CameraSpec with a given view).
CameraSpec fixedCamera(const Vec3& position, const Vec3& lookAt) {
  CameraSpec spec;
  spec.given = true;
  spec.position = position;
  spec.lookAt = lookAt;
  return spec;
}

std::vector<CameraKey> threeKeys() {
  return {CameraKey{0.0, Vec3(0, -10, 2), Vec3(0, 0, 0), 40},
          CameraKey{1.5, Vec3(8, -6, 5), Vec3(1, 1, 0.5), 30},
          CameraKey{4.0, Vec3(12, 4, 3), Vec3(2, 3, 1), 55}};
}

TEST(Camera, PathPassesThroughEveryKeyExactlyAndHoldsBeyondTheEnds) {
  const std::vector<CameraKey> keys = threeKeys();
  for (const CameraKey& k : keys) {
    const CameraView v = interpolateCameraPath(keys, k.time, Vec3::UnitZ());
    EXPECT_EQ(v.position, k.position) << "t = " << k.time;
    EXPECT_EQ(v.lookAt, k.lookAt) << "t = " << k.time;
    EXPECT_EQ(v.fovYDegrees, k.fovDegrees) << "t = " << k.time;
  }
  EXPECT_EQ(interpolateCameraPath(keys, -3, Vec3::UnitZ()).position, keys.front().position);
  EXPECT_EQ(interpolateCameraPath(keys, 99, Vec3::UnitZ()).lookAt, keys.back().lookAt);
  // Between keys it moves: not a step function.
  const Vec3 mid = interpolateCameraPath(keys, 0.75, Vec3::UnitZ()).position;
  EXPECT_GT((mid - keys[0].position).norm(), 1);
  EXPECT_GT((mid - keys[1].position).norm(), 1);
}

TEST(Camera, PathVelocityIsContinuousAtAKeyAndEqualsTheCatmullRomSlope) {
  // At the middle key the derivative from the left and from the right must both equal the
  // chord of the neighbouring keys over their time gap. One-sided differences over eps are off
  // by at most eps/2 * max |p''|; on a Hermite segment of h seconds |p''| <= (6 |dp| + 4 h |m0|
  // + 4 h |m1|) / h^2, under 60 units/s^2 for these keys (the fov's first segment: 54 deg/s^2),
  // so eps = 1e-6 s leaves under 3e-5; rounding adds ~1e-15 * 55 / 1e-6 = 6e-8.
  const std::vector<CameraKey> keys = threeKeys();
  const double t = keys[1].time, eps = 1e-6;
  const auto at = [&](double time) { return interpolateCameraPath(keys, time, Vec3::UnitZ()); };
  const Vec3 slope = (keys[2].position - keys[0].position) / (keys[2].time - keys[0].time);
  const Vec3 left = (at(t).position - at(t - eps).position) / eps;
  const Vec3 right = (at(t + eps).position - at(t).position) / eps;
  EXPECT_LT((left - slope).norm(), 1e-4);
  EXPECT_LT((right - slope).norm(), 1e-4);
  const double fovSlope = (keys[2].fovDegrees - keys[0].fovDegrees) / (keys[2].time - keys[0].time);
  EXPECT_NEAR((at(t).fovYDegrees - at(t - eps).fovYDegrees) / eps, fovSlope, 1e-4);
  EXPECT_NEAR((at(t + eps).fovYDegrees - at(t).fovYDegrees) / eps, fovSlope, 1e-4);
}

TEST(Camera, ChaseLagDecaysAsTheExponentialOfTheFormula) {
  // A target that jumps by 1 m: after n frames of dt the gap is exp(-n dt / T) exactly (the
  // factors exp(-dt/T) multiply), up to ~n roundings of 1e-16.
  const double dt = 1.0 / 30, T = 0.4;
  Vec3 c = Vec3::Zero();
  const Vec3 target(1, 0, 0);
  for (int n = 1; n <= 60; ++n) {
    c = chaseStep(c, target, dt, T);
    EXPECT_NEAR((target - c).norm(), std::exp(-n * dt / T), 1e-13) << "frame " << n;
  }
  // A target moving at v: the lag tends to v dt a / (1 - a), a = exp(-dt / T) (about v T).
  const Vec3 v(2, -1, 0.5);
  c = Vec3::Zero();
  Vec3 x = Vec3::Zero();
  for (int n = 1; n <= 600; ++n) {
    x += v * dt;
    c = chaseStep(c, x, dt, T);
  }
  const double a = std::exp(-dt / T);
  EXPECT_LT(((x - c) - v * (dt * a / (1 - a))).norm(), 1e-9);
  // T = 0: no lag at all.
  EXPECT_EQ(chaseStep(Vec3(5, 5, 5), Vec3(1, 2, 3), dt, 0), Vec3(1, 2, 3));
}

TEST(DrawList, ChaseCameraOfAGroupLooksAtTheSmoothedCentroid) {
  // Two bodies jump at frame 10 from around (0, 0, 1) to around (3, 0, 1): frame by frame the
  // camera's look-at point must follow chaseStep of the centroid, and frame k drawn after all
  // frames were observed must equal frame k drawn right after it was observed.
  CameraSpec spec = fixedCamera(Vec3(0, -6, 3), Vec3(0, 0, 1));
  spec.followGroup = {0, 1};
  spec.smoothing = 0.3;
  const auto shape = boxShape(Vec3(0.2, 0.2, 0.2));
  const auto posed = [&](int k) {
    const double x = k < 10 ? 0 : 3;
    return std::vector<BodyView>{body(shape, Vec3(x - 0.5, 0, 1)),
                                 body(shape, Vec3(x + 0.5, 0, 1))};
  };
  DrawListBuilder live(spec, 0.0, 1280, 720, 30);
  DrawListBuilder twoPass(spec, 0.0, 1280, 720, 30);
  std::vector<DrawList> liveLists;
  for (int k = 0; k < 40; ++k) liveLists.push_back(live.build(posed(k)));
  for (int k = 0; k < 40; ++k) twoPass.observe(posed(k));
  Vec3 expected(0, 0, 1);
  for (int k = 0; k < 40; ++k) {
    const Vec3 centroid(k < 10 ? 0 : 3, 0, 1);
    expected = k == 0 ? centroid : chaseStep(expected, centroid, 1.0 / 30, 0.3);
    const DrawList list = twoPass.build(posed(k), k);
    EXPECT_LT((list.camera.lookAt - expected).norm(), 1e-12) << "frame " << k;
    EXPECT_LT((list.camera.position - (expected + Vec3(0, -6, 2))).norm(), 1e-12);
    EXPECT_EQ(list.camera.lookAt, liveLists[static_cast<std::size_t>(k)].camera.lookAt);
  }
}

// A flat square terrain of side `size` m at z = 0, two triangles.
std::shared_ptr<TriMesh> flatTerrain(double size) {
  auto t = std::make_shared<TriMesh>();
  const double h = size / 2;
  t->vertices = {Vec3(-h, -h, 0), Vec3(h, -h, 0), Vec3(-h, h, 0), Vec3(h, h, 0)};
  t->triangles = {{0, 1, 3}, {0, 3, 2}};
  return t;
}

TEST(DrawList, AutomaticCameraFramesBodiesOnTheTerrainAndIgnoresOnesThatLeftIt) {
  const auto shape = boxShape(Vec3(0.5, 0.5, 0.5));
  const std::vector<BodyView> onTerrain{body(shape, Vec3(-20, 10, 0.5)),
                                        body(shape, Vec3(30, -15, 4))};
  std::vector<BodyView> bodies = onTerrain;
  bodies.push_back(body(shape, Vec3(400, 0, -30)));  // fell off the 200 m map
  bodies.push_back(body(shape, Vec3(0, 0, -500)));   // far below it (tunnelled, say)
  DrawListBuilder builder(CameraSpec{}, std::nullopt, 1280, 720, 30);
  builder.setTerrain(flatTerrain(200));
  EXPECT_TRUE(builder.onStage(bodies[0]));
  EXPECT_TRUE(builder.onStage(bodies[1]));
  EXPECT_FALSE(builder.onStage(bodies[2]));
  EXPECT_FALSE(builder.onStage(bodies[3]));
  const DrawList list = builder.build(bodies);
  const double aspect = 1280.0 / 720.0;
  for (const BodyView& b : onTerrain) {
    EXPECT_GE(frustumClearance(list.camera, aspect, b.x, 0.87), 0) << b.x.transpose();
  }
  // The leavers are not what the picture is about: the camera did not back off to show them.
  EXPECT_LT(frustumClearance(list.camera, aspect, bodies[2].x, 0), 0);
  EXPECT_LT(frustumClearance(list.camera, aspect, bodies[3].x, 0), 0);
  // Same camera as without them.
  DrawListBuilder without(CameraSpec{}, std::nullopt, 1280, 720, 30);
  without.setTerrain(flatTerrain(200));
  EXPECT_EQ(without.build(onTerrain).camera.position, list.camera.position);
}

TEST(DrawList, SmallBodiesInAWideShotAreDrawnAsMarkersOfTheMinimumSize) {
  CameraSpec spec = fixedCamera(Vec3(0, -1000, 200), Vec3(0, 0, 0));
  spec.minPixels = 6;
  const auto rock = boxShape(Vec3(0.3, 0.3, 0.3));  // 1 m across: about 1 pixel at 1 km
  const auto house = boxShape(Vec3(20, 20, 20));    // big enough as it is
  const std::vector<BodyView> bodies{body(rock, Vec3(10, 0, 0.3)), body(house, Vec3(-50, 0, 20))};
  DrawListBuilder builder(spec, 0.0, 1280, 720, 30);
  const DrawList list = builder.build(bodies);
  ASSERT_EQ(list.instances.size(), 2u);
  const DrawInstance& marker = list.instances[0];
  EXPECT_EQ(marker.surface, Surface::unlit);
  EXPECT_FALSE(marker.castsShadow);
  // Scaled about its centre so that it projects exactly min_pixels across.
  const double scale = marker.model.block<3, 1>(0, 0).norm();
  const double radius = builder.shapeRadius(rock);
  EXPECT_NEAR(projectedDiameter(list.camera, bodies[0].x, scale * radius, 720), 6, 1e-9);
  EXPECT_EQ(Vec3(marker.model.block<3, 1>(0, 3)), bodies[0].x);
  EXPECT_EQ(list.instances[1].surface, Surface::body);
  EXPECT_EQ(Mat3(list.instances[1].model.block<3, 3>(0, 0)), Mat3::Identity());
}

TEST(DrawList, ShadowMapFollowsTheViewAtKilometreScale) {
  // A 1 m rock on a 2.6 km terrain, seen from 60 m: fitted to all casters, one texel of a
  // 2048 map would be 2 * 1840 m / 2048 = 1.8 m and the rock would cast no visible shadow. The
  // map must give the rock at least 8 texels across.
  CameraSpec spec = fixedCamera(Vec3(40, -40, 30), Vec3(0, 0, 0));
  const auto rock = boxShape(Vec3(0.5, 0.5, 0.5));
  const std::vector<BodyView> bodies{body(rock, Vec3(0, 0, 0.5))};
  DrawListBuilder builder(spec, std::nullopt, 1280, 720, 30);
  builder.setTerrain(flatTerrain(2600));
  const DrawList list = builder.build(bodies);
  const ShadowProjection shadow =
      fitShadowProjection(list.sunDirection, list.casterCentre, list.casterRadius, 0, 2048);
  EXPECT_GE(1.0 / shadow.texelSize, 8) << "texel " << shadow.texelSize << " m";
  // And the rock itself is inside the map.
  const Vec4 c = shadow.viewProjection * Vec4(0, 0, 0.5, 1);
  EXPECT_LE(c.head<2>().cwiseAbs().maxCoeff(), 1.0);
}

TEST(DrawList, TrailsFollowTheBodyOverTheLastSeconds) {
  CameraSpec spec = fixedCamera(Vec3(0, -20, 2), Vec3(0, 0, 2));
  spec.trailSeconds = 0.5;  // 15 frames at 30 fps
  const auto shape = boxShape(Vec3(0.1, 0.1, 0.1));
  DrawListBuilder builder(spec, std::nullopt, 640, 360, 30);
  DrawList list;
  for (int k = 0; k < 40; ++k)
    list = builder.build(std::vector<BodyView>{body(shape, Vec3(0.1 * k, 0, 2))});
  ASSERT_EQ(list.instances.size(), 2u);  // the body and its trail
  const DrawInstance& trail = list.instances[1];
  EXPECT_EQ(trail.surface, Surface::unlit);
  const DrawMesh& mesh = list.meshes[static_cast<std::size_t>(trail.mesh)];
  EXPECT_TRUE(mesh.transient);
  // 15 segments, from x = 0.1 * 24 to 0.1 * 39, each a quad around the path.
  EXPECT_EQ(mesh.mesh->triangles.size(), 30u);
  double lo = 1e9, hi = -1e9;
  for (const Vec3& v : mesh.mesh->vertices) {
    lo = std::min(lo, v.x());
    hi = std::max(hi, v.x());
    EXPECT_NEAR(v.y(), 0, 1e-12);  // the ribbon faces the camera (it looks along +y)
    EXPECT_NEAR(v.z(), 2, 0.05);
  }
  EXPECT_NEAR(lo, 2.4, 1e-9);
  EXPECT_NEAR(hi, 3.9, 1e-9);
}

}  // namespace
}  // namespace vf

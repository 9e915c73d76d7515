// Rocks piled against the border of the terrain grid. The terrain is solid below its surface,
// so where a raised grid ends above the floor plane its border is a vertical wall
// (sim/collide/tree_terrain_descent.cpp, collideTreeHeightfield). Oracle: the true-mesh check
// (World::measure, through the Recorder at every frame) finds no rock inside another, inside
// the terrain, or below the floor by more than one leaf-voxel edge, as eq. 20 promises for every
// other contact (a leaf sphere moves less than its radius per step, so it is caught within one
// leaf of the surface it meets).
#include <gtest/gtest.h>

#include <algorithm>
#include <string>

#include "sim/ground/rock_fall.h"
#include "sim/ground/rock_monitor.h"
#include "sim/recorder.h"
#include "sim/scene/scene.h"
#include "tests/support/test_world.h"

namespace vf {
namespace {

// West border of scenes/terrain/cliff.asc, m: xllcorner 0 and samples at the centres of 0.5 m
// cells.
constexpr double kBorder = 0.25;

// The paper's cliff terrain (scenes/cliff.toml: its west border is the 9.5 m high top of the
// cliff, standing on the floor plane z = 0) with `count` rocks released together on the
// floor in two rows beside that border, 0.1 m above the floor, all moving towards it at 2 m/s:
// a pile pushed against the wall, as the rocks of the scale benchmark (Rockfall/N) that left
// the top of the cliff backwards.
SceneSpec pileAgainstTheWall(int count, bool extensions) {
  SceneSpec spec = loadScene(test::sourcePath("scenes/cliff.toml"));
  spec.level = 3;
  spec.duration = 2.0;
  spec.contactReduction = spec.sleep = extensions;
  spec.camera.followBody.reset();
  EmitterSpec& e = spec.emitters[0];
  e.count = count;
  e.start = 0;
  e.interval = 0;
  e.positions.clear();
  for (int row = 0; row < 2; ++row)
    for (int k = 0; k < count / 2; ++k)
      e.positions.push_back(Vec3(kBorder - 0.45 - 0.8 * row, 4 + 0.7 * k, 1));
  e.dropHeight = 0.1;
  e.velocity = Vec3(2, 0, 0);
  e.directionJitter = 0;
  return spec;
}

}  // namespace

TEST(TerrainWall, APileShovedAgainstTheGridBorderStaysOutOfTheTerrain) {
  for (bool extensions : {false, true}) {
    const SceneSpec spec = pileAgainstTheWall(30, extensions);
    BuiltScene built = buildScene(spec);
    World& w = *built.world;
    ASSERT_EQ(w.def().terrain->x0, kBorder);
    Recorder recorder(w, spec.fps, spec.duration);
    double reach = -INFINITY;  // easternmost mesh vertex over all frames, m
    for (int k = 0; k < recorder.frameCount(); ++k) {
      recorder.advanceToFrame(k);
      for (int i = 0; i < w.bodyCount(); ++i) {
        const BodyState& y = recorder.frameStates()[i];
        for (const Vec3& v : w.shape(i).mesh.vertices)
          reach = std::max(reach, (y.x + y.q.toRotationMatrix() * v).x());
      }
    }
    const RunSummary s = recorder.summary();
    const double edge = w.shape(0).tree->leaves().edge;  // one leaf-voxel edge, level 3
    EXPECT_LE(s.maxPenetrationBodyGround, edge) << "extensions " << extensions;
    EXPECT_LE(s.maxPenetrationBodyBody, edge) << "extensions " << extensions;
    EXPECT_EQ(s.tunnelled, 0) << "extensions " << extensions;
    // None was found below the surface (pushed out or buried by the rock monitor), and every
    // one is still on the floor side of the border: its centre west of it.
    for (const std::string& m : built.rockFall->terrainMessages()) ADD_FAILURE() << m;
    for (int i = 0; i < w.bodyCount(); ++i) {
      EXPECT_TRUE(w.isActive(i)) << "rock " << i;
      EXPECT_LT(w.state(i).x.x(), kBorder) << "rock " << i << " extensions " << extensions;
    }
    // They did reach the wall: some rock came within one leaf edge of it.
    EXPECT_GT(reach, kBorder - edge) << "extensions " << extensions;
  }
}

}  // namespace vf

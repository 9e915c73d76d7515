// The paper's examples (digest section 6), run from the shipped scene files exactly as the CLI
// runs them, checked against what the paper reports.
#include <gtest/gtest.h>

#include <algorithm>

#include "sim/recorder.h"
#include "sim/scene/scene.h"
#include "tests/support/test_world.h"

namespace vf {
namespace {

struct SceneRun {
  RunSummary summary;
  BuiltScene built;
  double maxSpeedAtEnd = 0;
};

SceneRun runScene(const std::string& name, std::optional<int> level = std::nullopt) {
  SceneSpec spec = loadScene(test::sourcePath("scenes/" + name + ".toml"));
  if (level) spec.level = *level;
  SceneRun run;
  run.built = buildScene(spec);
  Recorder recorder(*run.built.world, spec.fps, spec.duration);
  for (int k = 0; k < recorder.frameCount(); ++k) recorder.advanceToFrame(k);
  run.summary = recorder.summary();
  const World& w = *run.built.world;
  for (int i = 0; i < w.bodyCount(); ++i)
    if (w.isActive(i) && !w.isStatic(i))
      run.maxSpeedAtEnd = std::max(
          run.maxSpeedAtEnd, w.velocity(i).norm() + 0.5 * w.shape(i).diameter * w.angularVelocity(i).norm());
  return run;
}

double largestLeafEdge(const World& w) {
  double edge = 0;
  for (int i = 0; i < w.bodyCount(); ++i) edge = std::max(edge, w.shape(i).tree->leaves().edge);
  return edge;
}

// Example 1: cube B thrown at 5 m/s into cube A at rest; both rest by t = 2 s.
TEST(PaperScenes, Example1CubesComeToRestByTwoSeconds) {
  const SceneRun run = runScene("cubes");
  ASSERT_EQ(run.built.world->bodyCount(), 2);
  EXPECT_NEAR(run.built.world->time(), 2.0, 0.0);
  // At rest: no point of any body moves faster than gravity accelerates it in one step at the
  // largest step taken (anything faster is motion the integrator resolved, not rounding).
  EXPECT_LT(run.maxSpeedAtEnd, 9.81 * run.summary.totals.dtMax);
  EXPECT_EQ(run.summary.tunnelled, 0);
  // B hit A: A must have been pushed off its start (0, 0) (the paper's fig. 9 shows both move).
  EXPECT_GT(run.built.world->state(0).x.head<2>().norm(), 0.05);
}

// Example 2 at Lv 4 with the eq.-20 step: the paper reports no interpenetration. The spheres may
// overlap by at most one step's travel, which eq. 17 keeps below a leaf radius, so the true
// meshes may interpenetrate by at most one leaf-voxel edge.
TEST(PaperScenes, Example2BlocksAtLevel4NeverInterpenetrateMoreThanALeafEdge) {
  const SceneRun run = runScene("blocks", 4);
  const World& w = *run.built.world;
  ASSERT_EQ(w.bodyCount(), 10);
  for (int i = 0; i < w.bodyCount(); ++i) EXPECT_TRUE(w.isActive(i)) << "all 10 thrown by 5 s";
  const double edge = largestLeafEdge(w);
  EXPECT_LE(run.summary.maxPenetrationBodyBody, edge);
  EXPECT_LE(run.summary.maxPenetrationBodyGround, edge);
  EXPECT_EQ(run.summary.tunnelled, 0);
  EXPECT_GT(run.summary.totals.contacts, 0u) << "the blocks must actually collide";
}

// Same scene, same build: bit-identical trajectories (design.md, Determinism).
TEST(PaperScenes, TwoIdenticalRunsGiveTheSameChecksum) {
  const SceneRun a = runScene("blocks", 3);
  const SceneRun b = runScene("blocks", 3);
  EXPECT_EQ(a.summary.checksum, b.summary.checksum);
  EXPECT_EQ(a.summary.totals.steps, b.summary.totals.steps);
  // And the checksum sees physics: another level gives another trajectory.
  const SceneRun c = runScene("blocks", 2);
  EXPECT_NE(a.summary.checksum, c.summary.checksum);
}

}  // namespace
}  // namespace vf

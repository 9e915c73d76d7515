// Frames and steps kept apart: the step sequence depends on the scene alone,
// and frame k is the last step's state moved by free motion to t = k / fps.
#include "sim/recorder.h"

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <vector>

#include "sim/scene/scene.h"
#include "tests/support/test_world.h"

namespace vf {
namespace {

bool sameBits(const BodyState& a, const BodyState& b) {
  return a.x == b.x && a.q.coeffs() == b.q.coeffs() && a.P == b.P && a.L == b.L;
}

struct FpsRun {
  std::map<double, std::vector<BodyState>> frames;  // by frame time
  std::uint64_t checksum = 0;
  std::uint64_t steps = 0;
};

FpsRun runAt(double fps) {
  // Example 2: emitted blocks (release times), collisions with each other and the floor.
  SceneSpec spec = loadScene(test::sourcePath("scenes/blocks.toml"));
  spec.level = 3;  // keeps the four runs short; the property does not depend on the level
  for (ShapeSpec& s : spec.shapes) s.level.reset();
  spec.duration = 2.0;
  spec.fps = fps;
  BuiltScene built = buildScene(spec);
  Recorder recorder(*built.world, spec.fps, spec.duration);
  FpsRun run;
  for (int k = 0; k < recorder.frameCount(); ++k) {
    recorder.advanceToFrame(k);
    run.frames[recorder.frameTime(k)] = recorder.frameStates();
  }
  run.checksum = recorder.summary().checksum;
  run.steps = recorder.summary().totals.steps;
  return run;
}

TEST(Recorder, FrameRateDoesNotChangeThePhysics) {
  const FpsRun base = runAt(15);
  int compared = 0;
  for (const double fps : {25.0, 30.0, 60.0}) {
    const FpsRun other = runAt(fps);
    EXPECT_EQ(other.checksum, base.checksum) << "fps " << fps;
    EXPECT_EQ(other.steps, base.steps) << "fps " << fps;
    // Common frame times j / 5 s: k / fps rounds the same real number, so the keys match.
    for (int j = 0; j <= 10; ++j) {
      const double t = j / 5.0;
      ASSERT_TRUE(base.frames.count(t) && other.frames.count(t)) << "t = " << t;
      const auto& a = base.frames.at(t);
      const auto& b = other.frames.at(t);
      ASSERT_EQ(a.size(), b.size());
      for (std::size_t i = 0; i < a.size(); ++i) {
        EXPECT_TRUE(sameBits(a[i], b[i])) << "fps " << fps << ", t = " << t << ", body " << i;
        ++compared;
      }
    }
  }
  EXPECT_GT(compared, 0);
}

}  // namespace
}  // namespace vf

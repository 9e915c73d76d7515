// Frames and steps kept apart: the step sequence depends on the scene alone, and frame k is
// taken from the two step states that bracket t = k / fps (sim/frame_interp.h).
#include "sim/recorder.h"

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <vector>

#include "sim/frame_interp.h"
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

// A body in free flight tumbling about a non-principal axis, fixed 0.1 s steps, and every
// step state kept as the world made it.
struct Tumble {
  std::vector<StepState> steps;
  std::vector<std::vector<BodyState>> frames;
  std::vector<double> frameTimes;
};

Tumble tumble(double fps) {
  WorldDef def;
  def.step = StepRule::fixed(0.1);
  World world(def);
  BodyDef b = test::bodyAt(test::boxShape(0.4, 0.2, 0.1, 800, 2), Vec3(0, 0, 5));
  b.velocity = Vec3(1, 2, 3);
  b.angularVelocity = Vec3(3, -2, 5);
  world.addBody(b);
  Tumble t;
  auto keep = [&] { t.steps.push_back(StepState{world.time(), {world.state(0)}, {1}}); };
  keep();
  Recorder recorder(world, fps, 0.5);
  recorder.setAfterStep(keep);
  for (int k = 0; k < recorder.frameCount(); ++k) {
    recorder.advanceToFrame(k);
    t.frames.push_back(recorder.frameStates());
    t.frameTimes.push_back(recorder.frameTime(k));
  }
  return t;
}

TEST(Recorder, AFrameAtAStepTimeIsThatStepsState) {
  const Tumble t = tumble(10);  // frames at 0, 0.1, ..., 0.5: each a step time
  ASSERT_EQ(t.frames.size(), 6u);
  ASSERT_EQ(t.steps.size(), 6u);
  for (std::size_t k = 0; k < t.frames.size(); ++k)
    EXPECT_TRUE(sameBits(t.frames[k][0], t.steps[k].states[0])) << "frame " << k;
}

TEST(Recorder, AFrameBetweenStepsInterpolatesTheTwoStepStates) {
  const Tumble t = tumble(25);  // frames at 0.04 k: 0.04 and 0.08 inside the first step
  const BodyState& a = t.steps[0].states[0];
  const BodyState& b = t.steps[1].states[0];
  int checked = 0;
  for (std::size_t k = 0; k < t.frames.size(); ++k) {
    const double time = t.frameTimes[k];
    if (time <= 0 || time >= 0.1) continue;
    const double s = time / 0.1;
    const BodyState& y = t.frames[k][0];
    // By hand: x, P, L along the chord; q turned from a by the fraction s of the rotation
    // a^-1 b, as an angle about an axis (the short arc: a^-1 b with w >= 0).
    EXPECT_NEAR((y.x - (a.x + s * (b.x - a.x))).norm(), 0, 1e-14);
    EXPECT_NEAR((y.P - (a.P + s * (b.P - a.P))).norm(), 0, 1e-12);
    EXPECT_NEAR((y.L - (a.L + s * (b.L - a.L))).norm(), 0, 1e-12);
    Quat rel = a.q.conjugate() * b.q;
    if (rel.w() < 0) rel.coeffs() = -rel.coeffs();
    const Eigen::AngleAxisd turn(rel);
    const Quat expected = a.q * Quat(Eigen::AngleAxisd(s * turn.angle(), turn.axis()));
    EXPECT_GT(turn.angle(), 0.1) << "the step turns the body";
    EXPECT_NEAR(std::abs(y.q.dot(expected)), 1.0, 1e-14) << "t = " << time;
    EXPECT_NEAR((y.q.coeffs() - expected.coeffs()).norm(), 0, 1e-12) << "t = " << time;
    ++checked;
  }
  EXPECT_EQ(checked, 2);
}

TEST(FrameInterp, SlerpTakesTheShortArcAndKeepsEqualStatesToTheBit) {
  const Quat a(Eigen::AngleAxisd(0.3, Vec3(1, 2, 3).normalized()));
  Quat b(Eigen::AngleAxisd(0.9, Vec3(-1, 0, 2).normalized()));
  Quat minusB;
  minusB.coeffs() = -b.coeffs();
  // -b is the same rotation: the path from a is the same, not the long way round.
  const double arc = 2 * std::acos(std::abs(a.dot(b)));  // the rotation from a to b, rad
  for (const double s : {0.25, 0.5, 0.75}) {
    const Quat viaB = slerpShortArc(a, b, s), viaMinusB = slerpShortArc(a, minusB, s);
    EXPECT_NEAR(std::abs(viaB.dot(viaMinusB)), 1.0, 1e-15) << s;
    EXPECT_NEAR(2 * std::acos(std::min(1.0, std::abs(a.dot(viaMinusB)))), s * arc, 1e-7) << s;
  }
  EXPECT_TRUE(slerpShortArc(a, b, 0).coeffs() == a.coeffs());
  EXPECT_TRUE(slerpShortArc(a, a, 0.37).coeffs() == a.coeffs());
  BodyState y;
  y.x = Vec3(0.1, 100.3, 7);
  y.q = a;
  y.P = Vec3(1e-17, 0, -3e-18);
  y.L = Vec3(0, 2e-19, 0);
  EXPECT_TRUE(sameBits(interpolateBody(y, y, 0.3), y));
}

}  // namespace
}  // namespace vf

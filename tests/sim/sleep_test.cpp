// Sleeping (sim/solve/sleep.h) against what it promises:
//   - a body at rest on the floor falls asleep after SleepSettings::time, and then costs no
//     sphere test and does not move by a single bit;
//   - a body dropped onto a sleeping pile wakes it, and the three end up resting on each other
//     (no interpenetration, no tunnelling) and asleep again;
//   - a body drifting slower than the threshold in empty space never sleeps (it touches
//     nothing) and keeps its exact free-flight motion;
//   - the same run twice gives the same state hash (sleep decisions depend on the state only);
//   - StepStats::awake counts the bodies a step moves: none while all sleep, the woken pile
//     already in the step whose contact wakes it;
//   - a sleeping column woken by a light touch stays where it slept, with and without contact
//     reduction: its contacts start from the impulses that held it (contact_cache.h).
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "sim/world.h"
#include "tests/support/test_world.h"

namespace vf {
namespace {

WorldDef sleepingWorld() {
  WorldDef def;
  def.groundHeight = 0.0;
  def.sleep = true;
  return def;
}

TEST(Sleep, BodyAtRestSleepsAndThenCostsNothing) {
  World world(sleepingWorld());
  auto s = test::boxShape(0.3, 0.3, 0.3, 800, 3);
  world.addBody(test::bodyAt(s, Vec3(0, 0, test::restOffset(*s) + 0.2)));
  world.advanceTo(0.3);
  EXPECT_FALSE(world.isSleeping(0)) << "still falling or settling";
  EXPECT_EQ(world.lastStep().awake, 1u);
  world.advanceTo(3.0);  // lands at ~0.2 s, settles, then rests SleepSettings::time = 0.5 s
  ASSERT_TRUE(world.isSleeping(0));
  const BodyState before = world.state(0);
  world.advanceTo(4.0);
  EXPECT_EQ(world.lastStep().sphereTests, 0u);
  EXPECT_EQ(world.lastStep().contacts, 0u);
  EXPECT_EQ(world.lastStep().sleeping, 1u);
  EXPECT_EQ(world.lastStep().awake, 0u);
  EXPECT_EQ(world.state(0).x, before.x);
  EXPECT_EQ(world.state(0).q.coeffs(), before.q.coeffs());
  EXPECT_TRUE(world.state(0).P.isZero());
}

TEST(Sleep, DroppedBodyWakesThePileAndAllComeToRestAgain) {
  auto run = [] {
    World world(sleepingWorld());
    auto s = test::boxShape(0.3, 0.3, 0.3, 800, 3);
    const double lift = test::restOffset(*s);
    world.addBody(test::bodyAt(s, Vec3(0, 0, lift)));
    world.addBody(test::bodyAt(s, Vec3(0.02, 0, 3 * lift + 0.005)));
    BodyDef dropped = test::bodyAt(s, Vec3(-0.03, 0.01, 0), 2.5);
    dropped.dropHeight = 0.3;  // 0.3 m above the top of the pile at 2.5 s
    world.addBody(dropped);
    world.advanceTo(2.4);
    EXPECT_TRUE(world.isSleeping(0) && world.isSleeping(1)) << "the pile settled first";
    EXPECT_EQ(world.lastStep().awake, 0u) << "the pile asleep, the third body not yet released";
    bool woke = false;
    while (world.time() < 3.0) {
      world.step(1.0 / 60);
      const bool pileAwake = !world.isSleeping(0) && !world.isSleeping(1);
      // Counted once the touched island has woken: the step of the impact moves all three.
      if (world.time() > 2.5 + 1e-9) {
        EXPECT_EQ(world.lastStep().awake, pileAwake ? 3u : 1u) << "t = " << world.time();
      }
      woke = woke || pileAwake;
    }
    EXPECT_TRUE(woke) << "the impact must wake the pile (both bodies: one island)";
    world.advanceTo(6.0);
    for (int i = 0; i < 3; ++i) EXPECT_TRUE(world.isSleeping(i)) << "body " << i;
    // Resting on each other in order: each centre one box height (0.3 m, plus up to two leaf
    // sphere hulls, 2 * 2 * lift - 0.3 in all) above the one below.
    for (int i = 1; i < 3; ++i) {
      const double gap = world.state(i).x.z() - world.state(i - 1).x.z();
      EXPECT_GT(gap, 0.3);
      EXPECT_LT(gap, 2 * lift + 1e-3);
    }
    const Diagnostics d = world.measure();
    EXPECT_EQ(d.tunnelled, 0);
    EXPECT_EQ(d.maxPenetrationBodyBody, 0.0);
    return world.stateHash();
  };
  EXPECT_EQ(run(), run());
}

// Six boxes (0.55 x 0.4 x 0.25 m, 44 kg: example 4's) stacked and asleep; at 4.4 s a 0.1 kg
// box is set down on top, 2 mm above it, and wakes the whole column. Nothing pushes the column
// but that touch: all the momentum the small box can bring by then is what gravity gave it since
// its release, m g t, and spread over the column's mass M that moves it by at most
// (m g t / M) t in the time t watched. A column whose woken contacts started from zero instead
// sags by what the first passes miss (millimetres, most with contact reduction).
TEST(Sleep, WakingASleepingColumnLeavesItWhereItSlept) {
  for (bool reduce : {false, true}) {
    WorldDef def = sleepingWorld();
    def.contactReduction = reduce;
    World world(def);
    auto box = test::boxShape(0.55, 0.4, 0.25, 800, 3);
    auto touch = test::boxShape(0.1, 0.1, 0.1, 100, 3);
    constexpr int kBoxes = 6;
    for (int i = 0; i < kBoxes; ++i) {
      BodyDef b = test::bodyAt(box, Vec3::Zero(), 0.4 * i);
      b.dropHeight = 0.005;  // each set down on the one below
      world.addBody(b);
    }
    const double release = 0.4 * kBoxes + 2.0;
    BodyDef t = test::bodyAt(touch, Vec3::Zero(), release);
    t.dropHeight = 0.002;
    world.addBody(t);
    world.advanceTo(release - 0.1);
    std::vector<double> z;
    for (int i = 0; i < kBoxes; ++i) {
      ASSERT_TRUE(world.isSleeping(i)) << "box " << i << " with reduction " << reduce;
      z.push_back(world.state(i).x.z());
    }
    const double watched = 0.25;  // s, from 0.1 s before the release
    world.advanceTo(release - 0.1 + watched);
    EXPECT_FALSE(world.isSleeping(0)) << "the touch woke the column";
    const double bound = touch->mass * 9.81 * watched / (kBoxes * box->mass) * watched;
    for (int i = 0; i < kBoxes; ++i)
      EXPECT_LE(std::abs(world.state(i).x.z() - z[i]), bound)
          << "box " << i << " with reduction " << reduce;
  }
}

TEST(Sleep, SlowBodyInEmptySpaceNeverSleeps) {
  WorldDef def;
  def.gravity = Vec3::Zero();
  def.sleep = true;
  World world(def);
  auto s = test::boxShape(0.3, 0.3, 0.3, 800, 3);
  BodyDef b = test::bodyAt(s, Vec3::Zero());
  b.velocity = Vec3(0.01, 0, 0);  // a fifth of the sleep threshold
  world.addBody(b);
  world.advanceTo(5.0);
  EXPECT_FALSE(world.isSleeping(0));
  EXPECT_NEAR(world.state(0).x.x(), 0.05, 1e-12);  // 0.01 m/s for 5 s, to rounding
}

}  // namespace
}  // namespace vf

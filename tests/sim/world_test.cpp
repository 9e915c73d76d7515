// World bookkeeping: frame and release times, release warnings, the state hash.
#include "sim/world.h"

#include <gtest/gtest.h>

#include "tests/support/test_world.h"

namespace vf {
namespace {

TEST(World, ReleaseTimesOffByRoundingAreTakenAtTheFrameWithoutSliverSteps) {
  WorldDef def;
  World world(def);
  auto s = test::boxShape(0.2, 0.2, 0.2, 800, 2);
  const double release = 0.4 * 3;  // 1.2000000000000002, one ulp after the frame time 36/30
  world.addBody(test::bodyAt(s, Vec3(0, 0, 5), release));
  ASSERT_NE(release, 36 / 30.0);
  world.advanceTo(36 / 30.0);
  EXPECT_EQ(world.time(), release) << "the step lands on the release, a hair after the frame";
  EXPECT_TRUE(world.isActive(0)) << "released at the frame it rounds to";
  EXPECT_GT(world.totals().dtMin, 1e-6) << "no step shorter than rounding noise";
}

TEST(World, BodiesJoinExactlyAtTheirReleaseTime) {
  WorldDef def;
  def.gravity = Vec3::Zero();
  World world(def);
  auto s = test::boxShape(0.2, 0.2, 0.2, 800, 2);
  BodyDef b = test::bodyAt(s, Vec3(0, 0, 0), 0.25);
  b.velocity = Vec3(1, 0, 0);
  world.addBody(b);
  world.advanceTo(0.2);
  EXPECT_FALSE(world.isActive(0));
  EXPECT_EQ(world.state(0).x, Vec3::Zero()) << "inactive bodies do not move";
  world.advanceTo(1.0);
  // Moving at 1 m/s from t = 0.25 exactly: 0.75 m by t = 1, to rounding.
  EXPECT_NEAR(world.state(0).x.x(), 0.75, 1e-12);
}

TEST(World, ReleaseIntoAnotherBodyIsCounted) {
  WorldDef def;
  def.gravity = Vec3::Zero();
  World world(def);
  auto s = test::boxShape(0.2, 0.2, 0.2, 800, 3);
  world.addBody(test::bodyAt(s, Vec3(0, 0, 0)));
  world.addBody(test::bodyAt(s, Vec3(0.1, 0, 0), 0.1));  // overlaps body 0
  world.addBody(test::bodyAt(s, Vec3(3, 0, 0), 0.2));    // free space
  world.advanceTo(0.15);
  EXPECT_EQ(world.totals().overlappingReleases, 1u);
  world.advanceTo(0.3);
  EXPECT_EQ(world.totals().overlappingReleases, 1u);
}

TEST(World, DropHeightReleasesThatFarAboveWhatLiesBelow) {
  WorldDef def;
  def.groundHeight = 0.0;
  World world(def);
  auto s = test::boxShape(0.4, 0.4, 0.2, 800, 2);
  world.addBody(test::bodyAt(s, Vec3(0, 0, 0.1)));       // resting box, top at z = 0.2
  BodyDef over = test::bodyAt(s, Vec3(0.1, 0, 0), 0.5);  // z is ignored: placed at release
  over.dropHeight = 0.5;
  world.addBody(over);
  BodyDef beside = test::bodyAt(s, Vec3(3, 0, 7), 0.5);  // nothing below but the floor
  beside.dropHeight = 0.5;
  world.addBody(beside);
  world.advanceTo(0.5);
  // Bottom face (z - 0.1) exactly 0.5 m above the top of what is below, before any fall.
  EXPECT_NEAR(world.state(1).x.z() - 0.1, world.state(0).x.z() + 0.1 + 0.5, 1e-12);
  EXPECT_NEAR(world.state(2).x.z() - 0.1, 0.0 + 0.5, 1e-12);
}

TEST(World, AdvanceToNeverShortensAStepToMeetAFrame) {
  WorldDef def;
  def.fixedStep = 0.1;
  World world(def);
  world.addBody(test::bodyAt(test::boxShape(0.2, 0.2, 0.2, 800, 2), Vec3(0, 0, 5)));
  world.advanceTo(0.25);
  EXPECT_EQ(world.totals().steps, 2u);
  EXPECT_EQ(world.totals().dtMin, 0.1);
  EXPECT_EQ(world.time(), 0.1 + 0.1);
  EXPECT_GT(world.nextStepEnd(), 0.25);
}

TEST(World, StatesBetweenStepsAreFreeMotionOfACopy) {
  WorldDef def;
  def.fixedStep = 0.1;
  World world(def);
  const Vec3 x0(0, 0, 5), v0(1, 2, 3), w0(0, 0, 2);
  BodyDef b = test::bodyAt(test::boxShape(0.2, 0.2, 0.2, 800, 2), x0);
  b.velocity = v0;
  b.angularVelocity = w0;
  world.addBody(b);
  const std::uint64_t before = world.stateHash();
  const double t = 0.04;  // inside the first step
  const BodyState y = world.statesAt(t)[0];
  EXPECT_EQ(world.stateHash(), before) << "the simulated state is not touched";
  EXPECT_EQ(world.time(), 0.0);
  // One explicit Euler step of length t after gravity's increment, computed by hand: the
  // velocity first gains g t, then carries x; q turns by 1/2 [0, w] q t about z and is
  // renormalised (w stays along z for a body spinning about a principal axis).
  const Vec3 v = v0 + t * def.gravity;
  EXPECT_NEAR((y.x - (x0 + t * v)).norm(), 0, 1e-15);
  EXPECT_NEAR((world.velocity(0, y) - v).norm(), 0, 1e-14);
  const double half = 0.5 * w0.z() * t;  // q = (1, 0, 0, half) / |.|
  const double n = std::sqrt(1 + half * half);
  EXPECT_NEAR(y.q.w(), 1 / n, 1e-15);
  EXPECT_NEAR(y.q.z(), half / n, 1e-15);
}

TEST(World, StateHashSeesEveryBit) {
  WorldDef def;
  auto s = test::boxShape(0.2, 0.2, 0.2, 800, 2);
  World a(def), b(def);
  a.addBody(test::bodyAt(s, Vec3(0, 0, 1)));
  b.addBody(test::bodyAt(s, Vec3(0, 0, std::nextafter(1.0, 2.0))));
  EXPECT_NE(a.stateHash(), b.stateHash());
  World c(def);
  c.addBody(test::bodyAt(s, Vec3(0, 0, 1)));
  EXPECT_EQ(a.stateHash(), c.stateHash());
  a.advanceTo(0.5);
  c.advanceTo(0.5);
  EXPECT_EQ(a.stateHash(), c.stateHash());
}

// 40 boxes dropped in a column onto each other, spinning: enough collider pairs for two
// threads, and piles that settle.
void addPileOf40Boxes(World& world) {
  auto s = test::boxShape(0.3, 0.2, 0.2, 800, 3);
  for (int i = 0; i < 40; ++i) {
    BodyDef b = test::bodyAt(s, Vec3(0.13 * (i % 5), 0.11 * (i / 5 % 3), 0.2 + 0.25 * i));
    b.angularVelocity = Vec3(0.5 * (i % 3), 0.3, 0);
    world.addBody(b);
  }
}

// The world the pile falls in: a floor, `threads` narrow-phase threads, and contact reduction
// and sleeping when `extensions`.
WorldDef pileWorld(int threads, bool extensions) {
  WorldDef def;
  def.groundHeight = 0.0;
  def.threads = threads;
  def.contactReduction = extensions;
  def.sleep = extensions;
  return def;
}

// Threads share the narrow phase and the solver's islands and merge in a fixed order: a pile of
// 40 boxes (enough collider pairs and contacts for threads) gives the same state hash at every
// tenth of a second with 1, 2 and 3 threads, with and without the extensions that reorder work
// (reduction, sleeping).
TEST(World, StateHashDoesNotDependOnTheThreadCount) {
  for (const bool extensions : {false, true}) {
    auto run = [&](int threads) {
      World world(pileWorld(threads, extensions));
      addPileOf40Boxes(world);
      std::vector<std::uint64_t> hashes;
      for (int k = 1; k <= 20; ++k) {
        world.advanceTo(0.1 * k);
        hashes.push_back(world.stateHash());
      }
      return hashes;
    };
    const auto one = run(1);
    EXPECT_EQ(run(2), one) << (extensions ? "with" : "without") << " reduction and sleep";
    EXPECT_EQ(run(3), one) << (extensions ? "with" : "without") << " reduction and sleep";
  }
}

// Temporal coherence (narrow_phase.h, PairCandidates) is exact: the same pile of 40 boxes on
// the floor, with and without it (with it on two threads as well), gives the same state hash
// after every step, with and without the extensions; and the candidates must have served many
// pair tests, or the comparison would show nothing.
TEST(World, CoherenceChangesNoBitOfTheTrajectory) {
  for (const bool extensions : {false, true}) {
    auto run = [&](bool coherence, int threads, std::uint64_t& served) {
      WorldDef def = pileWorld(threads, extensions);
      def.coherence = coherence;
      World world(def);
      addPileOf40Boxes(world);
      std::vector<std::uint64_t> hashes;
      while (world.time() < 2.0) {
        world.stepNext();
        hashes.push_back(world.stateHash());
      }
      served = world.totals().pairsByCandidates;
      if (!coherence) {
        EXPECT_EQ(world.totals().pairsByCandidates, 0u);
      }
      return hashes;
    };
    std::uint64_t served = 0, unused = 0;
    const auto plain = run(false, 1, unused);
    EXPECT_EQ(run(true, 1, served), plain) << (extensions ? "with" : "without") << " extensions";
    EXPECT_EQ(run(true, 2, unused), plain) << "two threads";
    EXPECT_GT(served, plain.size()) << "candidates served fewer pair tests than there were steps";
  }
}

}  // namespace
}  // namespace vf

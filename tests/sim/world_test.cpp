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

TEST(World, ClearReleaseRaisesOnlyAReleaseBornInsideAnotherBody) {
  WorldDef def;
  def.gravity = Vec3::Zero();
  World world(def);
  auto s = test::boxShape(0.2, 0.2, 0.2, 800, 3);
  const double r = s->tree->leaves().radius;
  world.addBody(test::bodyAt(s, Vec3(0, 0, 0)));
  BodyDef into = test::bodyAt(s, Vec3(0.1, 0, 0), 0.1);  // overlaps body 0
  into.clearRelease = true;
  world.addBody(into);
  BodyDef free = test::bodyAt(s, Vec3(3, 0, 0.05), 0.2);  // meets nothing
  free.clearRelease = true;
  world.addBody(free);
  world.advanceTo(0.3);
  EXPECT_EQ(world.totals().overlappingReleases, 0u);
  // Raised until its bottom (z - 0.1) is on body 0's top (0.1) grown by both leaf radii.
  EXPECT_NEAR(world.state(1).x.z(), 0.2 + 2 * r, 1e-12);
  EXPECT_EQ(world.state(1).x.x(), 0.1);
  EXPECT_EQ(world.state(2).x.z(), 0.05) << "a release that meets nothing stays, to the bit";
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
  def.step = StepRule::fixed(0.1);
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
  def.step = StepRule::fixed(0.1);
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

// The state hash of the pile of 40 boxes in `def` at every tenth of a second, `tenths` of them.
std::vector<std::uint64_t> pileHashes(const WorldDef& def, int tenths) {
  World world(def);
  addPileOf40Boxes(world);
  std::vector<std::uint64_t> hashes;
  for (int k = 1; k <= tenths; ++k) {
    world.advanceTo(0.1 * k);
    hashes.push_back(world.stateHash());
  }
  return hashes;
}

// Threads share the narrow phase and the solver's islands and merge in a fixed order: a pile of
// 40 boxes (enough collider pairs and contacts for threads) gives the same state hash at every
// tenth of a second with 1, 2 and 3 threads, with and without the extensions that reorder work
// (reduction, sleeping).
TEST(World, StateHashDoesNotDependOnTheThreadCount) {
  for (const bool extensions : {false, true}) {
    auto run = [&](int threads) { return pileHashes(pileWorld(threads, extensions), 20); };
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

// The clearance rule (StepRule::clearance(), solve/time_step.h) keeps the bounds eq. 17
// gives while taking long steps in flight. Two experiments, each from ten starting points 3 cm
// apart, so that the last step before the impact ends at ten different distances (a rule that
// let a body step through its clearance would land some of them deep; checked by disabling the
// floor's and the pairs' bounds in turn):
//  - a box thrown down at 20 m/s from about 3 m, spinning, alone over the floor (eq. 20 at
//    level 3: steps of 1.26 ms; 1/60 s would carry it 0.33 m, 13 leaf radii);
//  - two boxes flying at each other at 20 m/s each, about 3 m apart, 2 m above the floor.
// Checked after every step by the true-mesh diagnostics: no mesh deeper in the floor than one
// leaf radius r, nor in another body than r_a + r_b = 2 r (a mesh vertex lies inside its leaf
// sphere, so the mesh is no deeper than the leaf spheres, which eq. 17 keeps within that bound
// per step). The impacts happen (the falling box bounces, the flying ones turn back); the first
// step, everything far apart, is the cap, 1/60 s, over ten times eq. 20's; each run takes
// fewer steps than with eq. 20.
TEST(World, ClearanceStepKeepsEq17BoundsWithFewerSteps) {
  auto s = test::boxShape(0.3, 0.2, 0.2, 800, 3);
  const double r = std::ldexp(s->diameter, -4);  // eq. 19 at level 3
  struct Outcome {
    double deepestFloor = 0, deepestBody = 0, firstStep = 0, turned = 0;
    std::uint64_t steps = 0;
  };
  auto run = [&](bool clearance, bool pair, double offset) {
    WorldDef def;
    def.groundHeight = 0.0;
    def.step = clearance ? StepRule::clearance() : StepRule::eq20();
    World world(def);
    if (pair) {
      BodyDef a = test::bodyAt(s, Vec3(0, 0, 2));
      a.velocity = Vec3(20, 0, 0);
      BodyDef b = test::bodyAt(s, Vec3(3 + offset, 0.02, 2));
      b.velocity = Vec3(-20, 0, 0);
      world.addBody(a);
      world.addBody(b);
    } else {
      BodyDef b = test::bodyAt(s, Vec3(0, 0, 3 + offset));
      b.velocity = Vec3(0, 0, -20);
      b.angularVelocity = Vec3(1, 2, 0);
      world.addBody(b);
    }
    Outcome o;
    while (world.time() < 0.3) {
      world.stepNext();
      if (o.firstStep == 0) o.firstStep = world.lastStep().dt;
      const Diagnostics d = world.measure();
      o.deepestFloor = std::max(o.deepestFloor, d.maxPenetrationBodyGround);
      o.deepestBody = std::max(o.deepestBody, d.maxPenetrationBodyBody);
      // Turned back: the falling box moving up, the first flyer moving to -x.
      o.turned = std::max(o.turned, pair ? -world.velocity(0).x() : world.velocity(0).z());
    }
    o.steps = world.totals().steps;
    return o;
  };
  for (const bool pair : {false, true})
    for (int k = 0; k < 10; ++k) {
      SCOPED_TRACE(std::string(pair ? "flying pair" : "falling box") + ", offset " +
                   std::to_string(0.03 * k));
      const Outcome eq20 = run(false, pair, 0.03 * k), clear = run(true, pair, 0.03 * k);
      EXPECT_LT(clear.deepestFloor, r);
      EXPECT_LT(clear.deepestBody, 2 * r);
      EXPECT_GT(clear.turned, 1.0) << "no impact";
      EXPECT_NEAR(clear.firstStep, 1.0 / 60, 1e-15);
      EXPECT_GT(clear.firstStep, 10 * eq20.firstStep);
      EXPECT_LT(clear.steps, eq20.steps);
    }
}

// The clearance rule decides from the state alone: the pile of 40 boxes gives the same state
// hashes on 1 and 2 threads with it, and not those of eq. 20 (the rule is in use).
TEST(World, ClearanceStepStateHashDoesNotDependOnTheThreadCount) {
  auto run = [&](int threads, bool clearance) {
    WorldDef def = pileWorld(threads, true);
    def.step = clearance ? StepRule::clearance() : StepRule::eq20();
    return pileHashes(def, 10);
  };
  const auto one = run(1, true);
  EXPECT_EQ(run(2, true), one);
  EXPECT_NE(run(1, false), one);
}

}  // namespace
}  // namespace vf

// Step listeners (sim/solve/step_listener.h): what an extension attached to a World sees, when,
// and how it stops a run.
#include "sim/solve/step_listener.h"

#include <gtest/gtest.h>

#include <memory>
#include <string>
#include <vector>

#include "sim/ground/forest_law.h"
#include "sim/ground/rock_fall_world.h"
#include "sim/world.h"
#include "tests/support/test_world.h"

namespace vf {
namespace {

// Writes each call as "phase t dt" (and the body for onRelease) into a shared log.
class PhaseLog : public StepListener {
 public:
  explicit PhaseLog(std::vector<std::string>& log) : log_(log) {}
  void beforeSolve(StepContext& c, SolverSettings&) override { note("beforeSolve", c); }
  void afterSolve(StepContext& c) override {
    note("afterSolve", c);
    contactsSeen = c.contacts.size();
  }
  std::optional<Runaway> beforeMove(const StepContext& c) override {
    note("beforeMove", c);
    return std::nullopt;
  }
  void afterIntegrate(StepContext& c) override { note("afterIntegrate", c); }
  void onRelease(StepContext& c, int id) override { note("onRelease " + std::to_string(id), c); }
  void afterStep(StepContext& c) override { note("afterStep", c); }
  std::size_t contactsSeen = 0;

 private:
  void note(const std::string& phase, const StepContext& c) {
    log_.push_back(phase + " " + std::to_string(c.time) + " " + std::to_string(c.dt));
  }
  std::vector<std::string>& log_;
};

TEST(StepListener, PhasesComeInStepOrderWithTheStepsClock) {
  // A box resting on the floor (contacts every step) and a second released at t = 0.01, before
  // the first step's 1/60 s would end: the first step ends at the release, the second has none.
  WorldDef def;
  def.groundHeight = 0.0;
  World world(def);
  std::vector<std::string> log;
  auto* rec = static_cast<PhaseLog*>(world.attach(std::make_unique<PhaseLog>(log)));
  world.addStepListener([&log](World&) { log.push_back("world"); });
  auto s = test::boxShape(0.2, 0.2, 0.2, 800, 2);
  world.addBody(test::bodyAt(s, Vec3(0, 0, test::restOffset(*s))));
  world.addBody(test::bodyAt(s, Vec3(2, 0, 1), 0.01));
  ASSERT_EQ(log, (std::vector<std::string>{"onRelease 0 0.000000 0.000000"}))
      << "a body active when added joins at once, outside any step";

  log.clear();
  world.stepNext();
  const std::string t0 = "0.000000", t1 = "0.010000", dt = std::to_string(world.lastStep().dt);
  ASSERT_EQ(world.time(), 0.01) << "the first step lands on the release";
  EXPECT_EQ(log, (std::vector<std::string>{
                     "beforeSolve " + t0 + " " + dt, "afterSolve " + t0 + " " + dt,
                     "beforeMove " + t0 + " " + dt, "afterIntegrate " + t1 + " " + dt,
                     "onRelease 1 " + t1 + " 0.000000", "afterStep " + t1 + " " + dt, "world"}));
  EXPECT_GT(rec->contactsSeen, 0u);
  EXPECT_EQ(rec->contactsSeen, world.contacts().size()) << "the contacts the step solved";

  log.clear();
  world.stepNext();
  EXPECT_EQ(log.size(), 6u) << "no release in the second step";
}

// Stops the run in its `at`-th step, naming body 0.
class Stopper : public StepListener {
 public:
  explicit Stopper(int at) : at_(at) {}
  std::optional<Runaway> beforeMove(const StepContext& c) override {
    if (++calls < at_) return std::nullopt;
    Runaway r;
    r.body = 0;
    r.shape = "box";
    r.time = c.time;
    r.quantity = "test";
    return r;
  }
  int calls = 0;

 private:
  int at_;
};

TEST(StepListener, ARunawayFromBeforeMoveStopsTheRunBeforeAnythingMoves) {
  WorldDef def;
  World world(def);
  auto* stop = static_cast<Stopper*>(world.attach(std::make_unique<Stopper>(3)));
  auto s = test::boxShape(0.2, 0.2, 0.2, 800, 2);
  world.addBody(test::bodyAt(s, Vec3(0, 0, 10)));
  world.step(0.01);
  world.step(0.01);
  const Vec3 x = world.state(0).x;
  const double t = world.time();
  const std::uint64_t steps = world.totals().steps;
  try {
    world.step(0.01);
    FAIL() << "the listener should have stopped the run";
  } catch (const RunawayError& e) {
    EXPECT_EQ(e.runaway().quantity, "test");
    EXPECT_EQ(e.runaway().time, t) << "the time of the step's start";
  }
  ASSERT_TRUE(world.runaway().has_value());
  EXPECT_EQ(world.state(0).x, x) << "stopped before the bodies moved";
  EXPECT_EQ(world.time(), t);
  EXPECT_EQ(world.totals().steps, steps) << "the stopped step is not counted";
  EXPECT_THROW(world.step(0.01), RunawayError);
  EXPECT_EQ(stop->calls, 3) << "a stopped world takes no more steps";
}

TEST(StepListener, AListenerAttachedLaterRunsBeforeTheRunGuard) {
  // A box thrown at 5 m/s, over a speed bound of 1 m/s: the run guard stops the first step in
  // beforeMove. A listener attached after the World was built stops it there too; the run's
  // reason is the listener's, so the guard came after it.
  WorldDef def;
  def.limits.maxSpeed = 1.0;
  World world(def);
  world.attach(std::make_unique<Stopper>(1));
  BodyDef b = test::bodyAt(test::boxShape(0.2, 0.2, 0.2, 800, 2), Vec3(0, 0, 10));
  b.velocity = Vec3(5, 0, 0);
  world.addBody(b);
  EXPECT_THROW(world.step(0.01), RunawayError);
  ASSERT_TRUE(world.runaway().has_value());
  EXPECT_EQ(world.runaway()->quantity, "test");

  World guarded(def);
  guarded.addBody(b);
  EXPECT_THROW(guarded.step(0.01), RunawayError);
  EXPECT_EQ(guarded.runaway()->quantity, "speed") << "the guard alone stops it";
}

// Rock fall attached where a world is built (sim/ground/rock_fall_world.h) takes the terrain and
// the floor from the world: a box sliding east off a 20 m grid at 3 m/s onto a floor plane level
// with it. The rock monitor, given the terrain, meets the box at addBody; given the floor, its
// `auto` edge keeps the box moving on the floor past the grid (without a floor it would remove
// it there, rockfall_test).
TEST(StepListener, RockFallTakesTheWorldsTerrainAndFloor) {
  WorldDef def;
  def.groundHeight = 0.0;
  def.terrain = std::make_shared<const Heightfield>(test::flatHeightfield(21, 21, 1.0, 0.0));
  def.contact.frictionBodyGround = 0.0;
  World world(def);
  const RockFall& rockFall = attachRockFall(world, {});
  auto s = test::boxShape(0.2, 0.2, 0.2, 800, 2);
  BodyDef b = test::bodyAt(s, Vec3(18, 10, test::restOffset(*s)));
  b.velocity = Vec3(3, 0, 0);
  world.addBody(b);
  ASSERT_EQ(rockFall.outcomes().size(), 1u) << "the monitor has the terrain";
  EXPECT_TRUE(rockFall.outcomes()[0].released);
  world.advanceTo(1.5);  // crosses x = 20 after 0.67 s
  EXPECT_GT(world.state(0).x.x(), 21.0);
  EXPECT_TRUE(world.isActive(0)) << "kept on the floor";
  EXPECT_EQ(rockFall.outcomes()[0].state, RockState::kMoving);
  EXPECT_TRUE(rockFall.terrainMessages().empty());
}

TEST(StepListener, IdleRockFallLeavesTheStepAsItWas) {
  // No ground map, forest or terrain: rock fall attached or not, the same states after every
  // step (the checksum), and its readouts are empty.
  WorldDef def;
  def.groundHeight = 0.0;
  auto s = test::boxShape(0.2, 0.2, 0.2, 800, 2);
  World plain(def);
  plain.addBody(test::bodyAt(s, Vec3(0, 0, 1)));
  plain.advanceTo(1.0);
  World world(def);
  const RockFall& rockFall = attachRockFall(world, {});
  world.addBody(test::bodyAt(s, Vec3(0, 0, 1)));
  world.advanceTo(1.0);
  EXPECT_EQ(world.stepsHash(), plain.stepsHash());
  EXPECT_TRUE(rockFall.outcomes().empty());
  EXPECT_FALSE(rockFall.allSettled(world.bodies()));
  EXPECT_TRUE(rockFall.stopReason().empty());
  EXPECT_TRUE(rockFall.terrainMessages().empty());
  EXPECT_EQ(rockFall.treeHits(0).hits, 0);
  EXPECT_EQ(rockFall.slippage(0), 0.0);
  EXPECT_EQ(rockFall.scarDepth(0), 0.0);
}

}  // namespace
}  // namespace vf

// World::stepToward(), behind step() and stepNext(), reads as the table of contents of one
// step (docs/architecture.md, "One step"):
//   step size (eq. 20)        solve/time_step.cpp
//   gravity                   solve/integrate.cpp
//   broad phase               collide/broad_phase.cpp
//   narrow phase (fig. 3)     collide/narrow_phase.cpp (waking sleepers: solve/sleep.cpp)
//   contact reduction         collide/contact_reduction.cpp (optional)
//   impulses (eq. 15)         solve/impulse.cpp, with the listeners' beforeSolve and afterSolve
//                             around it
//   listeners' beforeMove     may stop the run before anything moves (the run guard)
//   explicit Euler, renormalise q   solve/integrate.cpp; then the listeners' afterIntegrate
//   sleeping islands          solve/sleep.cpp (optional)
//   releases (emitters)       solve/release.cpp (drop-height placement); listeners' onRelease
//   listeners' afterStep, then the World-level step listeners (addStepListener)
// The step listeners (solve/step_listener.h) are what is not the paper's method: extensions,
// attached by whoever builds the world, and the run guard (run_guard.cpp), attached to every
// World and called after them.
// The diagnostics (World::measure) live in collide/penetration.cpp.
#include "sim/world.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "sim/collide/broad_phase.h"
#include "sim/collide/narrow_phase.h"
#include "sim/core/error.h"
#include "sim/core/hash.h"
#include "sim/solve/impulse.h"
#include "sim/solve/integrate.h"
#include "sim/solve/release.h"
#include "sim/solve/sleep.h"
#include "sim/solve/time_step.h"

namespace vf {

namespace {

using Clock = std::chrono::steady_clock;

// Stage timer of a step: seconds since the last lap (0 when timing is off).
class StageClock {
 public:
  explicit StageClock(bool on) : on_(on) {
    if (on_) last_ = Clock::now();
  }
  double lap() {
    if (!on_) return 0;
    const Clock::time_point now = Clock::now();
    const double s = std::chrono::duration<double>(now - last_).count();
    last_ = now;
    return s;
  }

 private:
  bool on_;
  Clock::time_point last_;
};

}  // namespace

void RunStats::add(const StepStats& s) {
  dtMin = steps == 0 ? s.dt : std::min(dtMin, s.dt);
  dtMax = steps == 0 ? s.dt : std::max(dtMax, s.dt);
  ++steps;
  pairs += s.pairs;
  sphereTests += s.sphereTests;
  contacts += s.contacts;
  nonFinite += s.nonFinite;
  floored += s.floored;
  overlappingReleases += s.overlappingReleases;
  leafContacts += s.leafContacts;
  solverPasses += s.solverPasses;
  pairsByCandidates += s.pairsByCandidates;
  pairsByDescent += s.pairsByDescent;
  awakeBodySteps += s.awake;
  sleepingBodySteps += s.sleeping;
  secondsStepSize += s.secondsStepSize;
  secondsPairs += s.secondsPairs;
  secondsContacts += s.secondsContacts;
  secondsSolve += s.secondsSolve;
  secondsIntegrate += s.secondsIntegrate;
  secondsSleep += s.secondsSleep;
  secondsRelease += s.secondsRelease;
}

World::World(WorldDef def) : def_(std::move(def)), stepsHash_(Hasher().value()) {
  if (def_.threads > 1) pool_ = std::make_unique<WorkerPool>(def_.threads);
  // The run guard checks every world's step, last: it sees the momenta every other listener
  // has left before anything moves.
  stepListeners_.push_back(std::make_unique<RunGuardListener>(def_.limits, def_.gravity));
}

StepListener* World::attach(std::unique_ptr<StepListener> listener) {
  VF_ASSERT(listener);
  return stepListeners_.insert(stepListeners_.end() - 1, std::move(listener))->get();
}

StepContext World::context(double dt) { return {bodies_, states_, contacts_, time_, dt}; }

int World::addBody(const BodyDef& d) {
  VF_ASSERT(d.shape && d.shape->tree && d.shape->mass > 0);
  BodyInfo b;
  b.shape = d.shape;
  b.isStatic = d.isStatic;
  b.releaseTime = d.releaseTime;
  b.dropHeight = d.dropHeight;
  b.clearRelease = d.clearRelease;
  b.active = d.releaseTime <= time_ + kTimeTolerance;
  BodyState y;
  y.x = d.position;
  y.q = d.orientation.normalized();
  if (!d.isStatic) {
    b.invMass = 1.0 / d.shape->mass;
    b.inertiaBodyInv = d.shape->inertiaBodyInv;
    const Mat3 R = y.q.toRotationMatrix();
    y.P = d.shape->mass * d.velocity;
    y.L = R * d.shape->inertiaBody * R.transpose() * d.angularVelocity;  // L = I(t) w
  }
  stableStepCache_ = std::numeric_limits<double>::quiet_NaN();
  const bool placeNow = b.active && b.dropHeight >= 0;
  bodies_.push_back(std::move(b));
  states_.push_back(y);
  if (placeNow) liftForRelease(bodyCount() - 1);
  if (bodies_.back().active) {
    StepContext c = context(0);
    for (const auto& l : stepListeners_) l->onRelease(c, bodyCount() - 1);
  }
  return bodyCount() - 1;
}

const StepStats& World::step(double maxDt) {
  VF_ASSERT(maxDt > 0);
  stepToward(time_ + maxDt);
  if (runaway_) throw RunawayError(*runaway_);
  foldStepHash();
  return last_;
}

double World::nextStepEnd() const {
  const double target = nextReleaseAfter(time_);
  const StepPlan plan = planStep(target);
  return plan.lands ? target : time_ + plan.dt;
}

const StepStats& World::stepNext() {
  stepToward(nextReleaseAfter(time_));
  if (runaway_) throw RunawayError(*runaway_);
  foldStepHash();
  return last_;
}

void World::advanceTo(double t, const std::function<void()>& afterStep) {
  // Frame times are k / fps and release times start + i * interval: where they are meant to
  // agree they can differ in the last bit, so a step ending a hair after t is taken too.
  while (nextStepEnd() <= t + kTimeTolerance) {
    stepNext();  // throws RunawayError when the run guard stopped the run
    if (afterStep) afterStep();
  }
}

// Free motion between steps, for an ensemble bake's frames (sim/ensemble/ensemble_bake.cpp); the
// recorder samples between two steps instead (sim/frame_interp.h). The copy moves as the next step
// would move it with no contacts (freeMotion: gravity's increment, then explicit Euler on x and q).
// So a body in flight is exactly where a step of length t - time() would put it, and a body resting
// on the ground shows at most gravity's sag |g| dt'^2 <= r (eq. 17).
std::vector<BodyState> World::statesAt(double t) const {
  std::vector<BodyState> states = states_;
  freeMotion(bodies_, states, def_.gravity, t - time_);
  return states;
}

void World::foldStepHash() {
  Hasher h;
  h.add(stepsHash_);
  h.add(stateHash());
  stepsHash_ = h.value();
}

double World::stableStep() const {
  if (std::isnan(stableStepCache_))
    stableStepCache_ = def_.step.isClearance()
                           ? clearanceStep(bodies_, states_, def_.gravity, def_.maxStep,
                                           def_.groundHeight, def_.terrain.get())
                           : vf::stableStep(bodies_, states_, def_.gravity, def_.maxStep);
  return stableStepCache_;
}

void World::stepToward(double target) {
  if (runaway_) return;
  StepStats s;
  StageClock clock(def_.stageTimes);

  const StepPlan plan = planStep(target);
  stableStepCache_ = std::numeric_limits<double>::quiet_NaN();  // the state changes from here on
  const bool lands = plan.lands;
  s.dt = plan.dt;
  s.floored = plan.floored ? 1 : 0;
  s.secondsStepSize = clock.lap();

  applyGravity(bodies_, states_, def_.gravity, s.dt);

  pairs_.clear();
  findPairs(bodies_, states_, pairs_, &sweepOrder_);
  s.pairs = pairs_.size();
  s.secondsPairs = clock.lap();

  findStepContacts(s);
  s.secondsContacts = clock.lap();

  solveStepContacts(s);
  s.secondsSolve = clock.lap();

  // The listeners may stop the run (the run guard) on the momenta of this step, before
  // anything moves.
  for (const auto& l : stepListeners_)
    if ((runaway_ = l->beforeMove(context(s.dt)))) return;

  s.nonFinite = integrate(bodies_, states_, s.dt, def_.rotation, pool_.get());
  time_ = lands ? target : time_ + s.dt;
  StepContext after = context(s.dt);
  for (const auto& l : stepListeners_) l->afterIntegrate(after);
  s.secondsIntegrate = clock.lap();

  if (def_.sleep) updateSleep(contacts_, bodies_, states_, s.dt, def_.sleepSettings);
  for (const BodyInfo& b : bodies_) s.sleeping += b.sleeping ? 1 : 0;
  s.secondsSleep = clock.lap();

  s.overlappingReleases = releaseBodies();
  for (const auto& l : stepListeners_) l->afterStep(after);
  s.secondsRelease = clock.lap();

  last_ = s;
  totals_.add(s);
  for (const auto& listener : listeners_) listener(*this);
}

void World::findStepContacts(StepStats& s) {
  // Contacts, reduced per collider pair by the narrow phase if asked (contact_reduction.h).
  const std::uint64_t served0 = candidates_.served, descents0 = candidates_.descents;
  auto contacts = [&] {
    contacts_.clear();
    const ContactCounts n =
        findContacts(bodies_, states_, pairs_, def_.groundHeight, def_.terrain.get(), pool_.get(),
                     contacts_, def_.coherence ? &candidates_ : nullptr, def_.contactReduction);
    s.sphereTests += n.sphereTests;
    s.leafContacts = n.leafContacts;
  };
  contacts();
  // Woken bodies start from rest with this step's gravity, and their own contacts (skipped
  // while they slept) are found again with everyone else's, in the usual order; repeated while
  // those wake further islands.
  for (std::vector<int> woken; def_.sleep && !(woken = wakeTouched(contacts_, bodies_)).empty();) {
    for (int i : woken) states_[i].P = (s.dt / bodies_[i].invMass) * def_.gravity;
    contacts();
  }
  for (const BodyInfo& b : bodies_) s.awake += b.moves() ? 1 : 0;
  s.pairsByCandidates = candidates_.served - served0;
  s.pairsByDescent = candidates_.descents - descents0;
  s.contacts = contacts_.size();
}

void World::solveStepContacts(StepStats& s) {
  SolverSettings solver;
  solver.material = def_.contact;
  // With contact reduction a patch rests on a few points instead of dozens, and Gauss-Seidel
  // over a few points converges slowly towards the solution (a box landing flat, three corner
  // leaves touching first, is left tilted by 0.01 rad after 12 point-by-point passes). So each
  // pass solves a patch's normal impulses together first (impulse.cpp, patch blocks), which
  // lands such a box in one pass, and the paper's 12 passes serve both.
  solver.iterations = def_.solverIterations;
  solver.patchBlocks = def_.contactReduction;
  solver.warmStartNearest = def_.contactReduction;  // representatives change keys (contact_cache)
  solver.restingSpeed = 2 * def_.gravity.norm() * s.dt;  // what gravity adds in two steps
  solver.dt = s.dt;
  solver.pool = pool_.get();
  int passes = 0;
  solver.passes = &passes;
  StepContext c = context(s.dt);
  for (const auto& l : stepListeners_) l->beforeSolve(c, solver);
  solveContacts(contacts_, bodies_, states_, solver, contactCache_);
  s.solverPasses = static_cast<std::uint64_t>(passes);
  for (const auto& l : stepListeners_) l->afterSolve(c);
}

World::StepPlan World::planStep(double target) const {
  // Step size: eq. 20 (or the fixed step), split so that `target` is reached in equal steps
  // none longer than the rule (solve/time_step.cpp). No target (infinity): the rule's step.
  StepPlan plan;
  const double fixed = def_.step.isFixed() ? def_.step.seconds : 0.0;
  plan.dt = chooseStep(target - time_, fixed, fixed > 0 ? 0.0 : stableStep(), def_.minStep,
                       plan.lands, plan.floored);
  return plan;
}

void World::liftForRelease(int id) {
  states_[id].x.z() += releaseLift(id, bodies_[id].dropHeight, bodies_, states_, contacts_,
                                   totals_.steps == 0, {def_.groundHeight, def_.terrain.get()});
}

std::uint64_t World::releaseBodies() {
  std::uint64_t overlapping = 0;
  for (int i = 0; i < bodyCount(); ++i) {
    BodyInfo& b = bodies_[i];
    if (b.active || b.releaseTime > time_ + kTimeTolerance) continue;
    if (b.dropHeight >= 0) liftForRelease(i);
    bool overlaps = overlapsActiveBody(i, bodies_, states_);
    if (overlaps && b.clearRelease) {
      states_[i].x.z() += releaseClearLift(i, bodies_, states_);
      overlaps = overlapsActiveBody(i, bodies_, states_);
    }
    overlapping += overlaps ? 1 : 0;
    b.active = true;
    StepContext c = context(0);
    for (const auto& l : stepListeners_) l->onRelease(c, i);
  }
  return overlapping;
}

double World::nextReleaseAfter(double t) const {
  double next = INFINITY;
  for (const BodyInfo& b : bodies_)
    if (!b.active && b.releaseTime > t + kTimeTolerance) next = std::min(next, b.releaseTime);
  return next;
}

void World::setMotion(int id, const Vec3& v, const Vec3& w) {
  BodyInfo& b = bodies_[id];
  if (b.isStatic) return;
  BodyState& y = states_[id];
  const Mat3 R = y.q.toRotationMatrix();
  y.P = b.shape->mass * v;
  y.L = R * b.shape->inertiaBody * R.transpose() * w;  // L = I(t) w
  if (v != Vec3::Zero() || w != Vec3::Zero()) b.sleeping = false, b.restTime = 0;
  stableStepCache_ = std::numeric_limits<double>::quiet_NaN();
}

void World::deactivate(int id) {
  bodies_[id].active = false;
  bodies_[id].releaseTime = INFINITY;  // never released again
  stableStepCache_ = std::numeric_limits<double>::quiet_NaN();
}

Vec3 World::velocity(int id) const { return velocity(id, states_[id]); }

Vec3 World::angularVelocity(int id) const { return angularVelocity(id, states_[id]); }

Vec3 World::velocity(int id, const BodyState& y) const { return velocityOf(bodies_[id], y); }

Vec3 World::angularVelocity(int id, const BodyState& y) const {
  return angularVelocityOf(bodies_[id], y);
}

std::uint64_t World::stateHash() const {
  Hasher h;
  h.add(time_);
  for (int i = 0; i < bodyCount(); ++i) {
    const BodyState& y = states_[i];
    h.add(static_cast<std::uint64_t>(bodies_[i].active));
    for (double v : {y.x.x(), y.x.y(), y.x.z(), y.q.w(), y.q.x(), y.q.y(), y.q.z(), y.P.x(),
                     y.P.y(), y.P.z(), y.L.x(), y.L.y(), y.L.z()})
      h.add(v);
  }
  return h.value();
}

Diagnostics World::measure() const { return measure(states_); }

Diagnostics World::measure(const std::vector<BodyState>& states) const {
  VF_ASSERT(static_cast<int>(states.size()) == bodyCount());
  return measureDiagnostics(bodies_, states, def_.gravity, def_.groundHeight, def_.terrain.get());
}

Diagnostics World::measure(const std::vector<BodyState>& states,
                           const std::vector<char>& active) const {
  VF_ASSERT(active.size() == bodies_.size());
  bool same = true;
  for (std::size_t i = 0; i < bodies_.size(); ++i)
    same = same && bodies_[i].active == (active[i] != 0);
  if (same) return measure(states);
  std::vector<BodyInfo> bodies = bodies_;
  for (std::size_t i = 0; i < bodies.size(); ++i) bodies[i].active = active[i] != 0;
  return measureDiagnostics(bodies, states, def_.gravity, def_.groundHeight, def_.terrain.get());
}

}  // namespace vf

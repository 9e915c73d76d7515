// The simulated world: immutable shapes, a compact array of body states, and step().
// Code that runs a simulation reaches the step through this class; the stages it calls live
// in sim/collide and sim/solve, and world.cpp lists them in step order. What is not the
// paper's method acts through step listeners (sim/solve/step_listener.h): extensions are
// attached by whoever builds the world (World::attach); the run guard (sim/run_guard.h), which
// guards every world's step, is attached by the World itself.
#pragma once

#include <cstdint>
#include <functional>
#include <limits>
#include <memory>
#include <optional>
#include <vector>

#include "sim/collide/contact.h"
#include "sim/collide/narrow_phase.h"
#include "sim/collide/penetration.h"
#include "sim/core/body.h"
#include "sim/core/math.h"
#include "sim/core/worker_pool.h"
#include "sim/run_guard.h"
#include "sim/shape/heightfield.h"
#include "sim/shape/shape.h"
#include "sim/solve/contact_cache.h"
#include "sim/solve/rotation_update.h"
#include "sim/solve/sleep.h"
#include "sim/solve/step_listener.h"
#include "sim/solve/time_step.h"

namespace vf {

// Times closer than this are the same instant, s: release times are computed as
// start + i * interval and frame times as k / fps, which can differ in the last bit where they
// are meant to agree.
inline constexpr double kTimeTolerance = 1e-9;

// Creation descriptor of a body (Box2D's *Def habit: every field has a default).
struct BodyDef {
  std::shared_ptr<const Shape> shape;
  Vec3 position = Vec3::Zero();         // centre of mass, m
  Quat orientation = Quat::Identity();  // body -> world
  Vec3 velocity = Vec3::Zero();         // of the centre of mass, m/s
  Vec3 angularVelocity = Vec3::Zero();  // rad/s, world frame
  bool isStatic = false;                // infinite mass: never moves
  double releaseTime = 0;               // joins the world at this time, s (emitters)
  // If >= 0, at release the body is moved vertically so that its lowest point is this far
  // above the highest point below its footprint (other bodies, floor, terrain), m.
  double dropHeight = -1;
  // If set, a release whose leaf spheres would touch another active body's is raised until its
  // mesh box clears the boxes of those bodies, grown by both leaf radii (releaseClearLift); a
  // release that touches nothing stays where it is, to the bit.
  bool clearRelease = false;
};

struct WorldDef {
  Vec3 gravity = Vec3(0, 0, -9.81);    // m/s^2
  StepRule step;                       // eq. 20 every step unless told otherwise (time_step.h)
  double maxStep = 1.0 / 60.0;         // s; upper bound of the eq.-20 step (bodies at rest)
  double minStep = 1e-6;               // s; floor of the eq.-20 step, so a runaway body (speeds
                                       // over ~1e4 m/s) cannot stall a run; counted in stats
  std::optional<double> groundHeight;  // floor plane z = h; none: no floor
  std::shared_ptr<const Heightfield> terrain;  // heightfield ground; none: no terrain
  ContactMaterial contact;
  int solverIterations = 12;  // sequential-impulse passes over the contacts
  // Extensions beyond the paper (docs/performance.md). Both change trajectories. A World built
  // in code gets the paper's method unless it asks for them; a scene file gets both unless it
  // says method = "paper" (SceneSpec).
  bool contactReduction = false;  // a few representative contacts per patch (contact_reduction.h)
  bool sleep = false;             // bodies at rest sleep until touched (solve/sleep.h)
  SleepSettings sleepSettings;
  // Threads for the narrow phase (blocks of collider pairs) and the solver (contact islands);
  // results are merged in a fixed order, so the trajectory and the checksum do not depend on it.
  int threads = 1;
  // Time every stage of every step (StepStats::seconds*; benchmarks and the paper's figures):
  // eight clock reads a step, several per cent of a step of one or two bodies. Off: those
  // fields stay 0.
  bool stageTimes = false;
  // Temporal coherence in the narrow phase (narrow_phase.h, PairCandidates): exact, the same
  // contacts; off only to test that.
  bool coherence = true;
  // Orientation update; the paper's explicit Euler by default, so the paper's scenes keep
  // their pinned trajectories (solve/integrate.h).
  RotationUpdate rotation = RotationUpdate::kExplicitEuler;
  RunLimits limits;  // runaway bounds checked every step (run_guard.h, RunGuardListener)
};

// What one step did. Counters are deterministic; the stage times are wall-clock and are never
// hashed or fed back into the simulation.
struct StepStats {
  double dt = 0;
  std::uint64_t pairs = 0;         // body pairs whose bounding spheres overlap
  std::uint64_t sphereTests = 0;   // sphere-sphere and sphere-plane tests in the narrow phase
  std::uint64_t leafContacts = 0;  // colliding leaf pairs the narrow phase found (before reduction)
  std::uint64_t contacts = 0;      // contacts handed to the solver (after reduction, if on)
  std::uint64_t solverPasses = 0;  // passes the solver made over the contacts
  // Sphere-tree collider pairs (body-body, body-plane) whose contacts came from last steps'
  // candidates, and those found by a descent (narrow_phase.h, PairCandidates).
  std::uint64_t pairsByCandidates = 0, pairsByDescent = 0;
  // Bodies the step moved: released, dynamic and awake once the sleeping islands that its
  // contacts touched had woken (BodyInfo::moves); what a step's cost grows with.
  std::uint64_t awake = 0;
  std::uint64_t sleeping = 0;             // bodies asleep at the end of the step
  std::uint64_t nonFinite = 0;            // bodies whose state went non-finite and were frozen
  std::uint64_t floored = 0;              // 1 if eq. 20 asked for less than WorldDef::minStep
  std::uint64_t overlappingReleases = 0;  // bodies released into another body's spheres
  // One timer per stage, in step order (0 unless WorldDef::stageTimes).
  // secondsContacts includes the contact reduction, made in the narrow phase.
  double secondsStepSize = 0, secondsPairs = 0, secondsContacts = 0, secondsSolve = 0,
         secondsIntegrate = 0, secondsSleep = 0, secondsRelease = 0;
};

// Totals over a run.
struct RunStats {
  std::uint64_t steps = 0;
  double dtMin = 0, dtMax = 0;
  std::uint64_t pairs = 0, sphereTests = 0, contacts = 0, nonFinite = 0, floored = 0;
  std::uint64_t overlappingReleases = 0;
  std::uint64_t leafContacts = 0;
  std::uint64_t solverPasses = 0;
  std::uint64_t pairsByCandidates = 0, pairsByDescent = 0;
  std::uint64_t awakeBodySteps = 0;     // sum over steps of the bodies moved (StepStats::awake)
  std::uint64_t sleepingBodySteps = 0;  // sum over steps of the bodies asleep
  double secondsStepSize = 0, secondsPairs = 0, secondsContacts = 0, secondsSolve = 0,
         secondsIntegrate = 0, secondsSleep = 0, secondsRelease = 0;
  void add(const StepStats& s);
};

class World {
 public:
  explicit World(WorldDef def);

  // Adds a body and returns its id (ids are dense, in order of addition).
  int addBody(const BodyDef& def);

  // Advances by one step towards time() + maxDt: maxDt itself when the step rule (eq. 20, the
  // clearance rule or the fixed step) allows it, else maxDt / n for the least n it allows.
  // Throws RunawayError if the run guard stopped the run (see runaway()); a body whose state
  // goes non-finite in the integration is frozen and counted in StepStats::nonFinite.
  const StepStats& step(double maxDt);

  // The scene's own step sequence. Output never steers the simulation (docs/rendering.md, "Frames
  // and steps"): each step is the eq.-20 (or fixed) step, split only so that release times are hit
  // exactly, so the steps depend on the bodies, their release times and the step rule alone, never
  // on a frame rate. Time at which the next step of that sequence ends, s.
  double nextStepEnd() const;
  // Takes the next step of the sequence. Throws RunawayError as step() does.
  const StepStats& stepNext();
  // Takes the steps of the sequence that end at or before t (a step ending within 1e-9 s after
  // t counts as ending at t). Never shortens a step to land on t: afterwards
  // time() <= t + 1e-9 < nextStepEnd(). Use statesAt(t) for the state at exactly t.
  // `afterStep`, when given, is called after every step (a bake records each one).
  // Throws RunawayError if the run guard stopped the run (see runaway()).
  void advanceTo(double t, const std::function<void()>& afterStep = {});
  // Set once a step listener's beforeMove stopped the run: the run guard at a non-finite state,
  // a body over limits.maxSpeed or an energy gain over the margin (run_guard.h); that step and
  // every later one throw RunawayError, the state that of the step before the bodies moved.
  const std::optional<Runaway>& runaway() const { return runaway_; }
  // Every body's state at time t, for t from time() up to nextStepEnd(): a COPY of the current
  // states moved by the step's own free motion over t - time() (gravity, then explicit Euler
  // on x and q; no contacts). The simulated state is not touched. Eq. 17 bounds what this can
  // show: under the eq.-20 rule no point of a body moves more than one leaf-sphere radius in a
  // whole step, so a partial step can neither carry a body through another nor sink it by more
  // than that radius. For t <= time() the current states are returned.
  std::vector<BodyState> statesAt(double t) const;
  // Hash of the state after every step taken so far (each folded in order): the trajectory
  // checksum. It depends on the steps only, so it is the same whatever frames are drawn.
  std::uint64_t stepsHash() const { return stepsHash_; }

  double time() const { return time_; }
  int bodyCount() const { return static_cast<int>(states_.size()); }
  const BodyState& state(int id) const { return states_[id]; }
  const Shape& shape(int id) const { return *bodies_[id].shape; }
  std::shared_ptr<const Shape> shapePtr(int id) const { return bodies_[id].shape; }
  bool isStatic(int id) const { return bodies_[id].isStatic; }
  // Released and simulated (bodies of an emitter join at their release time).
  bool isActive(int id) const { return bodies_[id].active; }
  // Asleep (WorldDef::sleep): at rest, not stepped until something touches it.
  bool isSleeping(int id) const { return bodies_[id].sleeping; }
  // Every body's record (shape, mass, flags), by id, as the step listeners see it.
  const std::vector<BodyInfo>& bodies() const { return bodies_; }
  Vec3 velocity(int id) const;         // m/s
  Vec3 angularVelocity(int id) const;  // rad/s, world frame
  // The same for body id in state y (e.g. one of statesAt(t)).
  Vec3 velocity(int id, const BodyState& y) const;         // m/s
  Vec3 angularVelocity(int id, const BodyState& y) const;  // rad/s, world frame
  const WorldDef& def() const { return def_; }
  const RunStats& totals() const { return totals_; }
  const StepStats& lastStep() const { return last_; }

  // The step rule's step for the current state (eq. 20, or the clearance rule when
  // WorldDef::step asks for it), before it is split to land on a release time or a step()'s end.
  double stableStep() const;
  // Hash of time and every body's state, bit-exact (see core/hash.h).
  std::uint64_t stateHash() const;
  // True-mesh diagnostics of the current state (collide/penetration.h): every surface sample of
  // each pair whose bounding spheres overlap, tested exactly through the other mesh's triangle
  // hierarchy: O(pairs * samples * log triangles); call per frame.
  Diagnostics measure() const;
  // The same for other states of these bodies (one per body, e.g. statesAt(t)).
  Diagnostics measure(const std::vector<BodyState>& states) const;
  // The same with other released flags (one per body, e.g. a frame's: Recorder::frameActive).
  Diagnostics measure(const std::vector<BodyState>& states, const std::vector<char>& active) const;

  // The contacts the last step solved (body ids a and b; b = kGround for the ground).
  const std::vector<Contact>& contacts() const { return contacts_; }
  // Policies acting between steps (barriers, sim/ground/barriers.h): gives dynamic body `id`
  // velocity v (m/s) and angular velocity w (rad/s, world frame), waking it when it moves; and
  // takes body `id` out of the world (it no longer collides, moves or draws).
  void setMotion(int id, const Vec3& v, const Vec3& w);
  void deactivate(int id);
  // Attaches `listener` to every later step, after the listeners attached before it and before
  // the run guard, which the constructor attaches and which stays last at every phase; returns
  // it, still owned by the World. A listener attached after a body was added has missed that
  // body's onRelease.
  StepListener* attach(std::unique_ptr<StepListener> listener);
  // Calls `listener` at the end of every step, after every StepListener's afterStep and before
  // the step's state is hashed: how a policy that needs the whole World, such as the barriers'
  // (setMotion, deactivate), acts on it without being part of the step. Listeners run in the
  // order added.
  void addStepListener(std::function<void(World&)> listener) {
    listeners_.push_back(std::move(listener));
  }

 private:
  // Steps once towards `target` (> time_), never past it; lands on it exactly when the step
  // rule allows reaching it in one step.
  void stepToward(double target);
  // Stages of stepToward that fill `s`: the contacts of the step (narrow phase, contact
  // reduction, waking sleepers), and the contact solve with the listeners around it.
  void findStepContacts(StepStats& s);
  void solveStepContacts(StepStats& s);
  // The step stepToward(target) would take: its length, whether it lands on `target`, and
  // whether eq. 20 asked for less than the floor.
  struct StepPlan {
    double dt = 0;
    bool lands = false;
    bool floored = false;
  };
  StepPlan planStep(double target) const;
  void foldStepHash();
  // The arrays and clock handed to the step listeners; dt 0 outside a step.
  StepContext context(double dt);
  // Activates bodies whose release time has come, each lifted by its drop height
  // (solve/release.h); returns how many of them were released overlapping an active body's
  // leaf spheres (an emitter aimed into a pile).
  std::uint64_t releaseBodies();
  // Lifts body `id` by its drop height above what lies under it (releaseLift).
  void liftForRelease(int id);
  double nextReleaseAfter(double t) const;

  WorldDef def_;
  double time_ = 0;
  std::vector<BodyInfo> bodies_;
  std::vector<BodyState> states_;
  RunStats totals_;
  StepStats last_;
  std::vector<BodyPair> pairs_;       // scratch, reused every step
  std::vector<int> sweepOrder_;       // the broad phase's last sweep order (findPairs)
  std::vector<Contact> contacts_;     // scratch, reused every step
  CandidateCache candidates_;         // leaf-pair candidates from step to step (narrow phase)
  std::unique_ptr<WorkerPool> pool_;  // def_.threads > 1: the threads of every step
  ContactCache contactCache_;         // last step's contact impulses (warm starting)
  std::uint64_t stepsHash_;           // see stepsHash()
  std::optional<Runaway> runaway_;    // see runaway()
  std::vector<std::unique_ptr<StepListener>> stepListeners_;  // attach(), the run guard last
  std::vector<std::function<void(World&)>> listeners_;        // addStepListener
  // stableStep() of the current state, NaN until asked: advanceTo asks for the next step's end
  // and the step then plans with the same state. Cleared wherever states_ or bodies_ change.
  mutable double stableStepCache_ = std::numeric_limits<double>::quiet_NaN();
};

}  // namespace vf

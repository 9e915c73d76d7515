// The simulated world: immutable shapes, a compact array of body states, and step().
// This is voxfall_sim's public interface; code outside sim/ includes only sim/*.h and
// sim/scene/scene.h.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "sim/collide/contact.h"
#include "sim/core/body.h"
#include "sim/core/math.h"
#include "sim/run_guard.h"
#include "sim/shape/heightfield.h"
#include "sim/shape/shape.h"

namespace vf {

// Rigid-body state y = {x, q, P, L} (eqs. 1-7): centre of mass (m), unit orientation
// quaternion (body -> world), linear momentum (kg m/s), angular momentum (kg m^2/s).
struct BodyState {
  Vec3 x = Vec3::Zero();
  Quat q = Quat::Identity();
  Vec3 P = Vec3::Zero();
  Vec3 L = Vec3::Zero();
};

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
};

// Restitution eps and kinetic friction mu per kind of contact pair (section 5 defaults).
struct ContactMaterial {
  double restitutionBodyBody = 0.5;
  double restitutionBodyGround = 0.3;
  double frictionBodyBody = 0.3;
  double frictionBodyGround = 0.8;
};

struct WorldDef {
  Vec3 gravity = Vec3(0, 0, -9.81);      // m/s^2
  double fixedStep = 0;                  // s; 0 selects the eq.-20 rule every step
  double maxStep = 1.0 / 60.0;           // s; upper bound of the eq.-20 step (bodies at rest)
  double minStep = 1e-6;                 // s; floor of the eq.-20 step, so a runaway body (speeds
                                         // over ~1e4 m/s) cannot stall a run; counted in stats
  std::optional<double> groundHeight;    // floor plane z = h; none: no floor
  std::shared_ptr<const Heightfield> terrain;  // heightfield ground; none: no terrain
  ContactMaterial contact;
  int solverIterations = 12;             // sequential-impulse passes over the contacts
  RunLimits limits;                      // runaway bounds checked every step (run_guard.h)
};

// What one step did. Counters are deterministic; the stage times are wall-clock and are never
// hashed or fed back into the simulation.
struct StepStats {
  double dt = 0;
  std::uint64_t pairs = 0;        // body pairs whose bounding spheres overlap
  std::uint64_t sphereTests = 0;  // sphere-sphere and sphere-plane tests in the narrow phase
  std::uint64_t contacts = 0;     // leaf contacts handed to the solver
  std::uint64_t nonFinite = 0;    // bodies whose state went non-finite and were frozen
  std::uint64_t floored = 0;      // 1 if eq. 20 asked for less than WorldDef::minStep
  std::uint64_t overlappingReleases = 0;  // bodies released into another body's spheres
  double secondsPairs = 0, secondsContacts = 0, secondsSolve = 0, secondsIntegrate = 0;
};

// Totals over a run.
struct RunStats {
  std::uint64_t steps = 0;
  double dtMin = 0, dtMax = 0;
  std::uint64_t pairs = 0, sphereTests = 0, contacts = 0, nonFinite = 0, floored = 0;
  std::uint64_t overlappingReleases = 0;
  double secondsPairs = 0, secondsContacts = 0, secondsSolve = 0, secondsIntegrate = 0;
  void add(const StepStats& s);
};

// Checks of the TRUE meshes (not the spheres) at one instant; see World::measure().
struct Diagnostics {
  double maxPenetrationBodyBody = 0;    // m, deepest point of one mesh inside another
  double maxPenetrationBodyGround = 0;  // m, deepest vertex below the floor or the terrain
  int tunnelled = 0;  // bodies whose centre of mass is inside another body or below the ground
  double kineticEnergy = 0;    // J, dynamic bodies
  double potentialEnergy = 0;  // J, -m g.x relative to the origin
};

class World {
 public:
  explicit World(WorldDef def);

  // Adds a body and returns its id (ids are dense, in order of addition).
  int addBody(const BodyDef& def);

  // Advances by one step of at most maxDt seconds (the eq.-20 or fixed step, whichever is
  // smaller). Never throws; numerical trouble is counted in the returned stats.
  const StepStats& step(double maxDt);
  // Steps until time() == t exactly (t >= time()). Release times on the way are hit exactly.
  // Throws RunawayError if the run guard stopped the run (see runaway()).
  void advanceTo(double t);
  // Set once a step found a non-finite state, a body over limits.maxSpeed or an energy gain
  // over the margin (run_guard.h); from then on steps do nothing.
  const std::optional<Runaway>& runaway() const { return runaway_; }
  const RunGuard& runGuard() const { return guard_; }

  double time() const { return time_; }
  int bodyCount() const { return static_cast<int>(states_.size()); }
  const BodyState& state(int id) const { return states_[id]; }
  const Shape& shape(int id) const { return *bodies_[id].shape; }
  std::shared_ptr<const Shape> shapePtr(int id) const { return bodies_[id].shape; }
  bool isStatic(int id) const { return bodies_[id].isStatic; }
  // Released and simulated (bodies of an emitter join at their release time).
  bool isActive(int id) const { return bodies_[id].active; }
  Vec3 velocity(int id) const;         // m/s
  Vec3 angularVelocity(int id) const;  // rad/s, world frame
  const WorldDef& def() const { return def_; }
  const RunStats& totals() const { return totals_; }
  const StepStats& lastStep() const { return last_; }

  // The eq.-20 step for the current state (before clamping to frame or release times).
  double stableStep() const;
  // Hash of time and every body's state, bit-exact (see core/hash.h).
  std::uint64_t stateHash() const;
  // True-mesh diagnostics of the current state: O(bodies^2 * mesh size); call per frame.
  Diagnostics measure() const;

 private:
  // Steps once towards `target` (> time_), never past it; lands on it exactly when the step
  // rule allows reaching it in one step.
  void stepToward(double target);
  // Activates bodies whose release time has come; returns how many of them were released
  // overlapping an active body's leaf spheres (an emitter aimed into a pile).
  std::uint64_t releaseBodies();
  // Lifts body `id` so its lowest point is `clearance` above the highest point under it:
  // floor, terrain, and bodies that touched something in the last step (and above any falling
  // body it would otherwise be born inside).
  void placeAbove(int id, double clearance);
  Eigen::AlignedBox3d worldBounds(int id) const;  // of the body's mesh in its current pose
  double nextReleaseAfter(double t) const;

  WorldDef def_;
  double time_ = 0;
  std::vector<BodyInfo> bodies_;
  std::vector<BodyState> states_;
  RunStats totals_;
  StepStats last_;
  std::vector<BodyPair> pairs_;     // scratch, reused every step
  std::vector<Contact> contacts_;   // scratch, reused every step
  ContactCache contactCache_;       // last step's contact impulses (warm starting)
  RunGuard guard_;
  std::optional<Runaway> runaway_;
};

}  // namespace vf

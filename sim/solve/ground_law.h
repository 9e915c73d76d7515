// What a rock loses where it meets the ground (rock fall extension; opt-in per ground material):
// STONE's three modes, flight, bounce and rolling, on a rigid body (ground_law.cpp).
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "sim/collide/contact.h"
#include "sim/core/body.h"
#include "sim/ground/ground_material.h"
#include "sim/shape/heightfield.h"

namespace vf {

// STONE's fixed mode parameters (Guzzetti et al. 2002, as the GRASS r.stone implementation
// sets them: DIST_FLY_ROLL, VEL_FLY_ROLL, and the lift-off height of its Roll step).
constexpr double kStoneShortBounce = 3.0;  // m: a landing this close to the last bounce ...
constexpr double kStoneRollSpeed = 5.0;    // m/s: ... and this slow starts rolling
constexpr double kStoneLiftOff = 0.01;     // m: a rolling rock this high above the ground flies

// What the law did in one step (counts of bodies).
struct GroundLawStats {
  int bounces = 0;           // landings that bounced (tangential restitution applied)
  int rolls = 0;             // landings that started rolling (short and slow)
  int braked = 0;            // bodies whose rolling spin the rolling resistance reduced
  std::vector<int> bounced;  // the bodies that bounced, in body order
};

// Per-body mode, kept across steps. Call beforeSolve() just before solveContacts and
// afterSolve() just after, every step, with the same contacts. Contacts on slip-law materials
// (slip_law.h) keep a body in contact but get no bounce and no rolling resistance.
class GroundLaw {
 public:
  // Remembers each body's velocity before the contact solve (the bounce's incoming velocity).
  void beforeSolve(const std::vector<BodyInfo>& bodies, const std::vector<BodyState>& states);
  // Body i's velocity as beforeSolve() saw it this step (m/s; the scar layer's impact speed).
  const Vec3& incomingVelocity(std::size_t i) const { return modes_[i].incoming; }

  // Per body with ground contacts (b == kGround) carrying normal impulse (N s, in contact
  // order): a landing after a flight bounces (its tangential velocity, spin included, kept to
  // at most Rt times the incoming one) unless it is short and slow, when the body rolls on;
  // every other step in contact brakes the rolling spin by a torque of at most mu_r h N, N the
  // sustained normal force (the summed normal impulse up to the weight's share m |g.n| dt). A
  // body without ground contact flies once its sphere tree is kStoneLiftOff clear of the
  // terrain and the floor plane.
  GroundLawStats afterSolve(const std::vector<Contact>& contacts,
                            const std::vector<double>& normalImpulses,
                            const std::vector<BodyInfo>& bodies, std::vector<BodyState>& states,
                            const GroundMap& ground, const Vec3& gravity, double dt,
                            const Heightfield* terrain, std::optional<double> floor);

 private:
  struct Mode {
    bool seen = false;           // the body has moved: lastBounce is its release point
    bool airborne = true;        // in flight since its last ground contact (STONE starts so)
    Vec3 lastBounce;             // where it last bounced (m)
    Vec3 incoming;               // velocity before this step's solve (m/s)
    Vec3 incomingSpin;           // angular momentum before this step's solve (kg m^2/s)
    std::uint32_t nearLeaf = 0;  // clearOfGround's hint: the leaf last found near the ground
  };
  // Sums the ground contacts of this step into the scratch below, per body of `bodyCount`.
  void sumGroundContacts(std::size_t bodyCount, const std::vector<Contact>& contacts,
                         const std::vector<double>& normalImpulses,
                         const std::vector<BodyState>& states, const GroundMap& ground);

  std::vector<Mode> modes_;
  // Per-step scratch, per body (kept to spare the step four allocations).
  std::vector<double> limit_, impulse_, stoneImpulse_, rt_;
  std::vector<Vec3> normal_;
};

// Whether every leaf sphere of the body is more than `height` above the ground below it: its
// centre's height above the terrain along the surface normal there, or above the floor plane,
// less its radius (a leaf over neither counts as clear). `hint` is a leaf to test first, where
// the last leaf found within `height` is put (any value will do: the answer is the same).
bool clearOfGround(const BodyInfo& b, const BodyState& y, const Heightfield* terrain,
                   std::optional<double> floor, double height, std::uint32_t& hint);

}  // namespace vf

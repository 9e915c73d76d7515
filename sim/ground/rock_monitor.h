// Rock fall bookkeeping after each step: what happens at the terrain's edges and holes, bodies
// found below the surface, when a rock counts as at rest, and each rock's outcome (release,
// stop or exit, runout, reach angle, maxima, path). Owned by the rock-fall step listener
// (rock_fall.h); reads and, for the edge policy and push-out, writes the body arrays.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "sim/core/body.h"
#include "sim/core/math.h"
#include "sim/ground/rock_monitor_settings.h"
#include "sim/shape/heightfield.h"

namespace vf {

struct BodyState;

enum class RockState { kMoving, kStopped, kLeft, kBuried };
const char* rockStateName(RockState s);

struct RockOutcome {
  bool released = false;
  Vec3 release = Vec3::Zero();  // centre of mass at release, world
  double releaseTime = 0;       // s
  RockState state = RockState::kMoving;
  Vec3 end = Vec3::Zero();            // stop or exit point (or last position while moving)
  double endTime = 0;                 // s
  double maxSpeed = 0;                // m/s
  double maxTranslationalEnergy = 0;  // J
  double maxRotationalEnergy = 0;     // J
  double maxJumpHeight = 0;           // m, lowest point of the body above the ground under it
  int bounces = 0;         // landings that bounced (STONE's Rt applied: sim/solve/ground_law.cpp)
  double restSince = -1;   // s, start of the current slow spell; < 0: none
  std::vector<Vec3> path;  // centre of mass, world, every RockMonitor::kPathInterval
  std::string message;     // why it left or was stopped (edge, hole, below the surface)
  double runout() const { return (end - release).head<2>().norm(); }  // horizontal, m
  // Reach angle (Fahrboeschung): atan of drop height over runout, degrees.
  double reachAngleDegrees() const;
};

class RockMonitor {
 public:
  static constexpr double kPathInterval = 0.1;  // s between path points

  // Body `id` bounced off the ground in this step (the ground law's count).
  void countBounce(int id);
  void configure(TerrainEdge edge, RestCriterion rest, const Heightfield* terrain,
                 std::optional<double> plane, const Vec3& gravity);
  // A body joins the world (at t = 0 or at its release time); one released below the terrain
  // surface is pushed out or stopped at once (as after a step).
  void onRelease(int id, double time, std::vector<BodyInfo>& bodies,
                 std::vector<BodyState>& states);
  // After the step that ended at `time`: edge and hole policy, push-out from below the
  // surface, rest, maxima, path. Returns the number of bodies removed or stopped this step.
  int afterStep(double time, std::vector<BodyInfo>& bodies, std::vector<BodyState>& states);

  const std::vector<RockOutcome>& outcomes() const { return rocks_; }
  // Every dynamic body released so far is at rest, gone or buried (and at least one was).
  bool allSettled(const std::vector<BodyInfo>& bodies) const;
  // Set when TerrainEdge::kStop fired: the run should end; names the rock and the time.
  const std::string& stopReason() const { return stopReason_; }
  // Messages of this run (bodies pushed out from below the surface, removed, buried), in order.
  const std::vector<std::string>& messages() const { return messages_; }

 private:
  // The ground under a point where the terrain's height there is h (NaN: no terrain data):
  // the terrain, else the plane, else NaN.
  double groundAtHeight(double h) const;
  // The rest criterion's clock for one rock after a step: `slow` this step (below the rest
  // speed), at `x` (world) at `time` (s); moves it between moving and stopped, and its end point.
  void updateRest(RockOutcome& r, bool slow, const Vec3& x, double time) const;
  // Body i's centre below the terrain surface (h: the surface's height under the centre):
  // pushed out along the normal when partly below (h then becomes the height under its new
  // place), stopped (buried) when wholly below; returns true when it was stopped.
  bool resolveBelowSurface(int i, double time, std::vector<BodyInfo>& bodies,
                           std::vector<BodyState>& states, double& h);
  void finish(int id, RockState state, const Vec3& where, double time, const std::string& why,
              std::vector<BodyInfo>& bodies, std::vector<BodyState>& states);

  TerrainEdge edge_ = TerrainEdge::kAuto;
  RestCriterion rest_;
  const Heightfield* terrain_ = nullptr;
  std::optional<double> plane_;
  Vec3 gravity_ = Vec3(0, 0, -9.81);
  std::vector<RockOutcome> rocks_;
  std::vector<Vec3> previous_;  // last position over ground, for the wall
  std::vector<double> nextPathTime_;
  std::string stopReason_;
  std::vector<std::string> messages_;
};

}  // namespace vf

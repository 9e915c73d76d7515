// Rock fall as an extension of the paper's step (docs/rockfall.md): one step listener that owns
// the laws and the bookkeeping a rock-fall run adds, and calls them where the step lets it:
//   before the contact solve   ground law (incoming velocities); the solver reads the ground
//                              map and the slip law's slippage s
//   after the contact solve    ground law (STONE: bounce, rolling; counts bounces for the
//                              monitor), scar drag, slip law (s over the step)
//   after the integration      forest law (stems met on the step's path)
//   at a release, after a step rock monitor (terrain: edges, holes, push-out, rest, outcomes)
// Each part acts only where its input is given: a ground map, a forest, terrain; with none of
// them the listener does nothing.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "sim/core/math.h"
#include "sim/ground/forest.h"
#include "sim/ground/forest_law.h"
#include "sim/ground/ground_material.h"
#include "sim/ground/rock_monitor.h"
#include "sim/shape/heightfield.h"
#include "sim/solve/ground_law.h"
#include "sim/solve/scar_drag.h"
#include "sim/solve/slip_law.h"
#include "sim/solve/step_listener.h"

namespace vf {

// Rock fall's own settings: what a caller gives attachRockFall (sim/ground/rock_fall_world.h),
// which takes the terrain, the floor and gravity from the world it attaches to.
struct RockFallDef {
  // Ground materials with STONE's law or the slip law (sim/ground/ground_material.h). Null: the
  // paper's model, [contact] body_ground for every ground contact.
  std::shared_ptr<const GroundMap> ground;
  // Stems hit statistically (forest_law.h), each body drawing from a stream of `forestSeed` and
  // its id (an ensemble draws the seed per realisation). Null: no trees.
  std::shared_ptr<const Forest> forest;
  std::uint64_t forestSeed = 1;
  // On terrain (rock_monitor.h): what lies beyond the grid and in NODATA cells, and when a rock
  // counts as at rest. Used only when the world has terrain.
  TerrainEdge terrainEdge = TerrainEdge::kAuto;
  RestCriterion rest;
};

// What rock fall reads of the world it is attached to.
struct RockFallGround {
  std::shared_ptr<const Heightfield> terrain;  // null: no rock monitor
  std::optional<double> floor;                 // the floor plane z = h, if any
  Vec3 gravity = Vec3(0, 0, -9.81);            // m/s^2
};

class RockFall : public StepListener {
 public:
  RockFall(RockFallDef def, RockFallGround world);
  const RockFallDef& def() const { return def_; }

  void beforeSolve(StepContext& c, SolverSettings& solver) override;
  void afterSolve(StepContext& c) override;
  void afterIntegrate(StepContext& c) override;
  void onRelease(StepContext& c, int id) override;
  void afterStep(StepContext& c) override;

  // Per body, its outcome so far (empty without terrain).
  const std::vector<RockOutcome>& outcomes() const { return monitor_.outcomes(); }
  // Every released dynamic body is at rest (RestCriterion), has left, or is buried.
  bool allSettled(const std::vector<BodyInfo>& bodies) const { return monitor_.allSettled(bodies); }
  // Non-empty when the run must end (TerrainEdge::kStop fired): names the rock and time.
  const std::string& stopReason() const { return monitor_.stopReason(); }
  // Bodies removed, stopped or pushed out from below the surface, with body and time.
  const std::vector<std::string>& terrainMessages() const { return monitor_.messages(); }
  // Stems body id met and the energy they took (zero without forest).
  TreeHits treeHits(int id) const { return forestLaw_.hits(id); }
  // The slip law's slippage s of body id (m): 0 without slip materials.
  double slippage(int id) const;
  // The scar depth d of body id (m): 0 out of contact with scar ground.
  double scarDepth(int id) const { return scarDrag_.depth(static_cast<std::size_t>(id)); }

 private:
  bool slip() const { return def_.ground && def_.ground->hasSlip(); }

  RockFallDef def_;
  RockFallGround world_;
  std::vector<double> normalImpulses_;  // per contact, from the solver, for the ground laws
  GroundLaw groundLaw_;                 // flight, bounce, rolling (per body)
  SlipLaw slipLaw_;                     // slippage s of the slip law (per body)
  ScarDrag scarDrag_;                   // the slip law's soft-soil scar layer
  RockMonitor monitor_;                 // terrain edges, push-out, rest, outcomes
  ForestLaw forestLaw_;                 // stems met in forest (per body)
};

}  // namespace vf

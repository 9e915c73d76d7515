// The rock-fall listener: each phase calls the laws in the order the step has always called
// them, so a rock-fall run takes the same floating-point operations as when they were part of
// the World.
#include "sim/ground/rock_fall.h"

#include <utility>

#include "sim/solve/impulse.h"

namespace vf {

RockFall::RockFall(RockFallDef def, RockFallGround world)
    : def_(std::move(def)), world_(std::move(world)) {
  monitor_.configure(def_.terrainEdge, def_.rest, world_.terrain.get(), world_.floor,
                     world_.gravity);
}

void RockFall::beforeSolve(StepContext& c, SolverSettings& solver) {
  solver.ground = def_.ground.get();
  solver.normalImpulses = def_.ground ? &normalImpulses_ : nullptr;
  if (def_.ground) groundLaw_.beforeSolve(c.bodies, c.states);
  if (slip()) {
    slipLaw_.resize(c.bodies.size());
    solver.slippage = &slipLaw_.slippage();
  }
}

void RockFall::afterSolve(StepContext& c) {
  if (!def_.ground) return;
  const GroundMap& ground = *def_.ground;
  const GroundLawStats law =
      groundLaw_.afterSolve(c.contacts, normalImpulses_, c.bodies, c.states, ground, world_.gravity,
                            c.dt, world_.terrain.get(), world_.floor);
  for (int id : law.bounced) monitor_.countBounce(id);
  if (!slip()) return;
  if (ground.hasScar())
    scarDrag_.afterSolve(c.contacts, normalImpulses_, c.bodies, c.states, ground, groundLaw_, c.dt,
                         world_.terrain.get(), world_.floor);
  slipLaw_.afterSolve(c.contacts, normalImpulses_, c.bodies, c.states, ground, c.dt);
}

void RockFall::afterIntegrate(StepContext& c) {
  if (def_.forest) forestLaw_.afterStep(*def_.forest, def_.forestSeed, c.bodies, c.states);
}

void RockFall::onRelease(StepContext& c, int id) {
  if (world_.terrain && !c.bodies[static_cast<std::size_t>(id)].isStatic)
    monitor_.onRelease(id, c.time, c.bodies, c.states);
}

void RockFall::afterStep(StepContext& c) {
  if (world_.terrain) monitor_.afterStep(c.time, c.bodies, c.states);
}

double RockFall::slippage(int id) const {
  const std::vector<double>& s = slipLaw_.slippage();
  return static_cast<std::size_t>(id) < s.size() ? s[static_cast<std::size_t>(id)] : 0.0;
}

}  // namespace vf

// attachRockFall: rock fall built from its settings and the world's ground and gravity.
#include "sim/ground/rock_fall_world.h"

#include <memory>
#include <utility>

#include "sim/core/error.h"

namespace vf {

RockFall& attachRockFall(World& world, RockFallDef def) {
  VF_ASSERT(world.bodyCount() == 0);
  const WorldDef& w = world.def();
  auto rockFall = std::make_unique<RockFall>(std::move(def),
                                             RockFallGround{w.terrain, w.groundHeight, w.gravity});
  RockFall& attached = *rockFall;
  world.attach(std::move(rockFall));
  return attached;
}

}  // namespace vf

// Rock fall attached to a World: the one place a world gets the rock-fall step listener
// (sim/ground/rock_fall.h). Whoever builds a world attaches it there: a scene
// (sim/scene/scene_build.cpp), an ensemble's realisation (sim/ensemble/ensemble.cpp), a test.
#pragma once

#include "sim/ground/rock_fall.h"
#include "sim/world.h"

namespace vf {

// Attaches rock fall with settings `def` to `world`, which must have no body yet (the rock
// monitor meets every body at its release), and returns it, owned by the world. It takes the
// terrain, the floor and gravity from world.def(). It runs before the run guard at every phase
// (World::attach); with no ground map, forest or terrain it does nothing.
RockFall& attachRockFall(World& world, RockFallDef def);

}  // namespace vf

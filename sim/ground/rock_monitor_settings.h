// The rock monitor's settings (rock_monitor.h), apart from the monitor so that a scene's spec
// (sim/scene/scene.h) can carry them without seeing rock fall's laws.
#pragma once

namespace vf {

// What lies beyond the terrain grid and in its NODATA cells.
enum class TerrainEdge {
  kAuto,    // kRemove, except in a scene with a floor plane, where the plane catches rocks
            // (the paper's cliff scene: keeps its trajectories)
  kRemove,  // the rock leaves the simulation; where and when is recorded
  kStop,    // the run ends, naming the rock and the time
  kWall,    // a vertical wall: the rock is put back and its horizontal velocity reflected
};

// "At rest": speed below `speed` and spin times the body's radius below `speed`, for `time`
// seconds without a break. voxfall's decision (the literature's lumped-mass codes stop a rock
// the first time it is slower than 0.5 m/s, RockGIS, or 1 m/s, r.stone's example): a held
// threshold does not call a rock stopped at the top of a bounce.
struct RestCriterion {
  double speed = 0.1;  // m/s
  double time = 1.0;   // s
};

}  // namespace vf

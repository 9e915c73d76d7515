// Barriers (docs/rockfall.md, "Barriers"): rockfall nets or walls along a polyline, built as
// static bodies the rocks collide with, and the capacity rule applied at a rock's first contact
// with one. The geometry goes through the World like any static body (the step knows nothing of
// barriers); the rule observes the world after each step and acts on the rock it touched, as
// the ground law's bookkeeping does outside the collision code.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "sim/shape/heightfield.h"
#include "sim/shape/shape.h"
#include "sim/world.h"

namespace vf {

struct Barrier {
  std::string name;
  std::vector<std::array<double, 2>> points;  // world x, y, m; at least two
  double height = 3;                          // m above the ground
  double capacity = 0;                        // J: energy it absorbs at a hit
  double thickness = 0.3;                     // m
};

// How deep a barrier piece reaches below the lowest ground under it, m: uneven ground along a
// piece leaves no gap under the wall.
inline constexpr double kBarrierEmbed = 0.5;

// The static pieces of a barrier: each segment split into the fewest equal pieces no longer than
// the barrier's height (so a piece's voxels, edge = its longest side / 2^level, stay a small
// fraction of the height), each a box of the segment's direction, `thickness` thick, from
// kBarrierEmbed below the lowest ground under it up to `height` above the ground at its middle.
struct BarrierPiece {
  std::shared_ptr<const Shape> shape;
  Vec3 position = Vec3::Zero();  // centre, world
  Quat orientation = Quat::Identity();
};
std::vector<BarrierPiece> barrierPieces(const Barrier& barrier, const Heightfield& terrain,
                                        int level);

// What a barrier met over a run.
struct BarrierResult {
  std::int64_t hits = 0;     // rocks that touched it (each rock once)
  std::int64_t stopped = 0;  // of those, stopped: kinetic energy at the hit <= capacity
  std::int64_t passed = 0;   // of those, through it with the excess: the barrier failed
  double maxEnergy = 0;      // J, largest kinetic energy at a hit
  bool failed = false;       // a rock broke through; it is gone for the rest of the run
};

class BarrierMonitor {
 public:
  BarrierMonitor() = default;
  // `bodies[b]`: the ids of barrier b's static bodies in the world.
  BarrierMonitor(std::vector<Barrier> barriers, std::vector<std::vector<int>> bodies);
  // Adds the pieces of every barrier to `world` as static bodies and returns the monitor.
  static BarrierMonitor build(World& world, const std::vector<Barrier>& barriers,
                              const std::vector<std::vector<BarrierPiece>>& pieces);
  // Before the first step and after every step: the capacity rule at each rock's first contact
  // with a barrier (the step's contacts); the energy at the hit is the rock's at the step state
  // before it.
  void observe(World& world);
  const std::vector<BarrierResult>& results() const { return results_; }
  const std::vector<Barrier>& barriers() const { return barriers_; }
  bool empty() const { return barriers_.empty(); }

 private:
  struct Motion {
    bool valid = false;
    Vec3 v = Vec3::Zero(), w = Vec3::Zero();
    double energy = 0;  // J
  };
  std::vector<Barrier> barriers_;
  std::vector<std::vector<int>> bodies_;
  std::vector<int> barrierOf_;  // per body id: its barrier, or -1
  std::vector<BarrierResult> results_;
  std::vector<Motion> last_;                  // per body, at the last observation
  std::vector<std::pair<int, int>> handled_;  // (rock, barrier) hits already ruled on
};

}  // namespace vf

// Evaluation lines (docs/rockfall.md, "Evaluation lines"): polylines in plan whose vertical
// curtains record every crossing of a rock's centre of mass, with its time, place, velocity,
// kinetic energies and passing height, and the per-line statistics made of them.
//
// Crossings are found on the world's own step states, never on output frames: the centre of
// mass moves along a straight segment between two consecutive step states, and a crossing is
// that segment meeting a line segment in plan. So they are the same whatever the frame rate,
// and the same bits for any thread count (the step states are). The recorder observes a World
// from outside its step (the step knows nothing of lines), as the ensemble's cell passages do.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "sim/core/math.h"
#include "sim/world.h"

namespace vf {

// One evaluation line: a polyline of at least two vertices, world x, y (m).
struct EvaluationLine {
  std::string name;
  std::vector<std::array<double, 2>> points;
};

// One crossing of a line by a rock's centre of mass.
struct LineCrossing {
  std::int32_t line = 0;           // index into the lines
  std::int64_t rock = 0;           // the body id (simulate) or the realisation index (ensemble)
  double time = 0;                 // s
  Vec3 point = Vec3::Zero();       // centre of mass at the crossing, world, m
  Vec3 velocity = Vec3::Zero();    // of the centre of mass, m/s
  double translationalEnergy = 0;  // J, m |v|^2 / 2 at the crossing
  double rotationalEnergy = 0;     // J, w.L / 2, interpolated between the two step states
  // m, the centre of mass above the ground (terrain, else floor plane) vertically under it;
  // NaN over no ground.
  double height = 0;
  // +1: from the line's left to its right, walking from its first vertex to its last; -1: back.
  std::int32_t direction = 0;
  double energy() const { return translationalEnergy + rotationalEnergy; }
};

// Where the plan segment a -> b (world x, y of two consecutive centre-of-mass positions) crosses
// `line`: per crossing, the fraction s in (0, 1] along a -> b and the direction. A segment
// parallel to a line segment never crosses it; a crossing exactly at a vertex between two line
// segments counts once (each line segment holds its first end, the last also its second).
struct CurtainHit {
  double s = 0;
  std::int32_t direction = 0;
};
void curtainHits(const std::vector<std::array<double, 2>>& line, const Vec3& a, const Vec3& b,
                 std::vector<CurtainHit>& out);

// Records the crossings of a running World. Call observe() once before the first step and after
// every step (World::advanceTo's afterStep, or after each stepNext).
class CrossingRecorder {
 public:
  explicit CrossingRecorder(std::vector<EvaluationLine> lines) : lines_(std::move(lines)) {}
  // `rockOfBody`, when not negative, is the `rock` every crossing records (an ensemble's
  // realisation index); otherwise the body id.
  void observe(const World& world, std::int64_t rockOfBody = -1);
  const std::vector<LineCrossing>& crossings() const { return crossings_; }
  const std::vector<EvaluationLine>& lines() const { return lines_; }

 private:
  struct StepState {
    bool valid = false;  // active and dynamic at the last observation
    double time = 0;
    Vec3 x = Vec3::Zero(), v = Vec3::Zero();
    double rotationalEnergy = 0;
  };
  std::vector<EvaluationLine> lines_;
  std::vector<StepState> last_;
  std::vector<LineCrossing> crossings_;
  std::vector<CurtainHit> hits_;  // scratch
};

// A line's statistics over the crossings of `rocks` rocks (realisations, or released bodies).
struct LineSummary {
  std::string name;
  std::int64_t crossings = 0;      // every crossing, in either direction
  std::int64_t rocksCrossing = 0;  // rocks that crossed it at least once
  std::int64_t rocks = 0;
  double probability = 0;  // rocksCrossing / rocks
  // Nearest-rank percentiles 50, 95, 99 over the crossings (sim/ensemble/ensemble_stats.h) of
  // the total kinetic energy (J) and the passing height (m); NaN without crossings.
  std::array<double, 3> energy{}, height{};
};
inline constexpr std::array<int, 3> kLinePercentiles = {50, 95, 99};
std::vector<LineSummary> summariseLines(const std::vector<EvaluationLine>& lines,
                                        const std::vector<LineCrossing>& crossings,
                                        std::int64_t rocks);

}  // namespace vf

// Hazard ensembles (README, "Ensembles and hazard maps"): many independent realisations of a
// scene's [ensemble] release, each one rock in its own World, reduced into per-cell statistics
// on the DEM's grid (ensemble_stats.h).
//
// Reproducibility: realisation i draws everything from one Prng seeded by realisationSeed(S,
// i), a function of the ensemble seed S and i alone, so it can be rerun alone (`--only i`) and
// gives the same trajectory whatever the number of threads or processes. The terrain, the
// ground map and the shapes (sphere trees) are built once and shared read-only by every
// realisation and thread.
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "sim/core/math.h"
#include "sim/ensemble/release_sources.h"
#include "sim/ground/rock_fall.h"
#include "sim/ground/rock_monitor.h"
#include "sim/scene/scene.h"
#include "sim/shape/heightfield.h"
#include "sim/world.h"

namespace vf {

// What a realisation did in one DEM cell it passed: the largest values over the steps whose
// centre-of-mass segment met the cell (see Ensemble::run).
struct CellPassage {
  std::int32_t cell = 0;  // j * nx + i on the DEM grid (Heightfield::z's layout)
  double energy = 0;      // J, kinetic energy, translational + rotational
  double height = 0;      // m, lowest point of the rock above the ground under its centre, >= 0
  double speed = 0;       // m/s, of the centre of mass
};

// A point of a realisation's centre-of-mass path (every step), world coordinates.
struct PathPoint {
  double time = 0;  // s
  Vec3 x = Vec3::Zero();
};

// One realisation's outcome.
struct RealisationResult {
  std::int64_t index = 0;
  std::uint64_t seed = 0;
  bool complete = false;                 // false: abandoned by a stop request
  int shape = 0;                         // index into EnsembleSpec::shapes
  Vec3 release = Vec3::Zero();           // centre of mass at release, world, m
  Vec3 end = Vec3::Zero();               // stop or exit point, or the last position, world, m
  double endTime = 0;                    // s
  RockState state = RockState::kMoving;  // kMoving: still moving at the scene's duration
  double runout = 0;                     // horizontal, m
  double reachAngle = 0;                 // degrees
  double maxSpeed = 0;                   // m/s
  double maxEnergy = 0;                  // J, kinetic, translational + rotational
  double maxJumpHeight = 0;              // m (RockOutcome::maxJumpHeight)
  double volume = 0;                     // m^3, of the rock as released
  double mass = 0;                       // kg
  int treeHits = 0;                      // stems of [forest] the rock met (TreeHits::hits)
  double treeEnergy = 0;                 // J, kinetic energy those stems took
  std::int64_t steps = 0;
  std::uint64_t checksum = 0;           // World::stepsHash(): the trajectory, bit for bit
  std::vector<CellPassage> cells;       // sorted by cell, each cell once
  std::vector<PathPoint> path;          // every step, only when asked for
  std::vector<LineCrossing> crossings;  // of the scene's evaluation lines, in time order
  std::vector<BarrierResult> barriers;  // per [[barriers]] barrier (sim/ground/barriers.h)
};

// The seed of realisation i of an ensemble with seed S: SplitMix64 of (SplitMix64(S) + i).
std::uint64_t realisationSeed(std::uint64_t ensembleSeed, std::int64_t index);

// The cells of the DEM's grid (pixel (i, j) is the square of side `cell` centred on sample
// (i, j)) met by the segment a -> b (world x, y), in the order the segment meets them; cells
// off the grid are skipped. A zero-length segment meets the cell that holds it.
void cellsOnSegment(const Heightfield& dem, const Vec3& a, const Vec3& b,
                    std::vector<std::int32_t>& out);

// A realisation's World before its first step, with what is attached to it.
struct RealisationWorld {
  std::unique_ptr<World> world;  // one dynamic body, id 0, then the barriers' static pieces
  RockFall* rockFall = nullptr;  // attached to `world`: the rock's outcome
  std::shared_ptr<const BarrierMonitor> barriers;  // null without [[barriers]]
  int shape = 0;                                   // index into EnsembleSpec::shapes
};

class Ensemble {
 public:
  // Builds the terrain, ground map and shapes of `spec` once and checks the release: throws
  // InputError naming the key when a release point lies off the DEM or over NODATA, or when the
  // source raster is not on the DEM's grid. `spec` must have an [ensemble] table.
  explicit Ensemble(const SceneSpec& spec);

  // Runs realisation `index` with seed `seed` to its end: the rock stops (RestCriterion),
  // leaves the DEM or is buried (sim/ground/rock_monitor.h), or the scene's duration is
  // reached. Safe to call from several threads at once. `stop`, when given, is polled between
  // steps; when it returns true the realisation is abandoned (complete = false). With
  // `keepPath`, every step's centre of mass is kept in `path`.
  RealisationResult run(std::int64_t index, std::uint64_t seed, bool keepPath,
                        const std::function<bool()>& stop = {}) const;
  // The World of the realisation with seed `seed` before its first step, with rock fall (the
  // forest drawn with the realisation's own seed) and the barriers attached.
  RealisationWorld makeWorld(std::uint64_t seed) const;
  const std::vector<Barrier>& barriers() const { return barriers_; }

  const SceneSpec& spec() const { return spec_; }
  const EnsembleSpec& ensemble() const { return *spec_.ensemble; }
  const Heightfield& dem() const { return *base_.terrain; }
  // The scene's forest stand on the DEM's grid, or null without [forest].
  const Forest* forest() const { return rockFall_.forest.get(); }
  // The release sources as world x, y outlines for maps (ReleaseSources::outlines).
  std::vector<std::vector<Point2>> releaseAreas() const;
  // The scene's evaluation lines, world coordinates (sceneEvaluationLines).
  const std::vector<EvaluationLine>& lines() const { return lines_; }

 private:
  SceneSpec spec_;
  WorldDef base_;
  RockFallDef rockFall_;  // the scene's; each realisation draws its own forest seed and ground
  std::vector<std::shared_ptr<const Shape>> shapes_;  // per EnsembleSpec::shapes entry
  std::shared_ptr<const ReleaseSources> release_;

  // `shape` at the volume and density realisation's size generator draws for release source
  // `source` ([ensemble] volume and density), or `shape` itself without them.
  std::shared_ptr<const Shape> sized(const std::shared_ptr<const Shape>& shape, int source,
                                     std::uint64_t seed) const;
  std::vector<EvaluationLine> lines_;
  std::vector<Barrier> barriers_;
  std::vector<std::vector<BarrierPiece>> barrierPieces_;  // built once, shared by every world
};

// Runs realisations `indices` of `ensemble` on `jobs` threads (each takes the next index in
// turn); results come back in the order of `indices`, so what is made of them does not
// depend on `jobs`. `progress(done)` is called on the calling thread a few times a second;
// `stop` is polled by every worker between steps. `onResult`, when given, receives each
// complete realisation on the calling thread, in the order they finish (for a journal or MPI,
// which then need no lock and see one thread only).
std::vector<RealisationResult> runRealisations(
    const Ensemble& ensemble, const std::vector<std::int64_t>& indices, std::uint64_t ensembleSeed,
    int jobs, bool keepPaths, const std::function<void(int)>& progress,
    const std::function<bool()>& stop,
    const std::function<void(const RealisationResult&)>& onResult = {});

// Results as bytes and back (MPI and the journal; same architecture on every rank). One
// result is appended to `bytes`, or read from `bytes` at `pos` (advanced past it); InputError
// when the bytes end early.
void serializeResult(const RealisationResult& result, std::string& bytes);
RealisationResult deserializeResult(const std::string& bytes, std::size_t& pos);
std::string serializeResults(const std::vector<RealisationResult>& results);
std::vector<RealisationResult> deserializeResults(const std::string& bytes);

}  // namespace vf

// Hazard ensembles: one realisation = one rock in its own World (see ensemble.h).
//
// Passages. A realisation passes a DEM cell (the pixel square centred on a DEM sample) when
// the straight segment between its centre of mass before and after some step meets the cell;
// the release cell counts. Under the eq.-20 rule a step moves a rock by at most about one
// leaf-sphere radius (eq. 17), far less than a DEM cell, so the segments follow the
// trajectory closely and a rock cannot jump over a cell it flew across. Each segment is walked
// through the grid cell by cell (cellsOnSegment), so no cell on the way is missed, and the
// cell is given the larger of the values at the segment's two ends (energy, height above
// ground, speed); a realisation keeps, per cell, the largest over all its segments there.
#include "sim/ensemble/ensemble.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstring>
#include <mutex>
#include <stdexcept>
#include <string>
#include <thread>
#include <type_traits>

#include "sim/core/error.h"
#include "sim/core/prng.h"
#include "sim/ensemble/block_size.h"
#include "sim/ground/rock_fall_world.h"
#include "sim/run_guard.h"

namespace vf {
namespace {

// Kinetic energy of body 0, J, and its lowest point's height above the ground under its centre.
struct SampleValues {
  double energy = 0, height = 0, speed = 0;
};

SampleValues sample(const World& w, const Heightfield& dem) {
  SampleValues s;
  const BodyState& y = w.state(0);
  const Vec3 v = w.velocity(0);
  const Vec3 om = w.angularVelocity(0);
  s.speed = v.norm();
  s.energy = 0.5 * w.shape(0).mass * v.squaredNorm() + 0.5 * y.L.dot(om);
  const double g = dem.heightAt(y.x.x(), y.x.y());
  if (!std::isnan(g)) {
    const Mat3 R = y.q.toRotationMatrix();
    double lowest = INFINITY;
    for (const Vec3& p : w.shape(0).mesh.vertices) lowest = std::min(lowest, (R * p).z());
    s.height = std::max(0.0, y.x.z() + lowest - g);
  }
  return s;
}

// The maxima of a realisation's passage through each DEM cell its path meets (a realisation
// meets each cell once).
class CellMaxima {
 public:
  CellMaxima(const Heightfield& dem, std::vector<CellPassage>& cells) : dem_(dem), cells_(cells) {}
  // The segment a -> b of the path, with the largest values along it.
  void add(const Vec3& a, const Vec3& b, const SampleValues& v) {
    met_.clear();
    cellsOnSegment(dem_, a, b, met_);
    for (std::int32_t c : met_) {
      auto [it, added] = seen_.emplace(c, cells_.size());
      if (added) cells_.push_back(CellPassage{c, 0, 0, 0});
      CellPassage& p = cells_[it->second];
      p.energy = std::max(p.energy, v.energy);
      p.height = std::max(p.height, v.height);
      p.speed = std::max(p.speed, v.speed);
    }
  }

 private:
  const Heightfield& dem_;
  std::vector<CellPassage>& cells_;
  std::map<std::int32_t, std::size_t> seen_;  // per cell met, the index of its entry in cells_
  std::vector<std::int32_t> met_;
};

// The rock's outcome and the run's totals, read from its world at the end of the run.
void readOutcome(const World& w, const RockFall& rockFall, RealisationResult& r) {
  const RockOutcome& o = rockFall.outcomes()[0];
  r.release = o.release;
  r.end = o.end;
  r.endTime = o.endTime;
  r.state = o.state;
  r.runout = o.runout();
  r.reachAngle = o.reachAngleDegrees();
  r.maxSpeed = o.maxSpeed;
  r.maxJumpHeight = o.maxJumpHeight;
  r.volume = w.shape(0).volume;
  r.mass = w.shape(0).mass;
  const TreeHits trees = rockFall.treeHits(0);
  r.treeHits = trees.hits;
  r.treeEnergy = trees.absorbed;
  r.steps = static_cast<std::int64_t>(w.totals().steps);
  r.checksum = w.stepsHash();
}

// The shape a uniform u in [0, 1) draws, each with its weight (the last one should rounding
// leave u * total past the sum).
int drawShape(const EnsembleSpec& e, double u) {
  double totalWeight = 0;
  for (double w : e.weights) totalWeight += w;
  int shape = static_cast<int>(e.shapes.size()) - 1;
  double cumulative = 0;
  for (std::size_t k = 0; k < e.weights.size(); ++k) {
    cumulative += e.weights[k];
    if (u * totalWeight < cumulative) {
      shape = static_cast<int>(k);
      break;
    }
  }
  return shape;
}

// The point a fraction u of the way through the range [lo, hi].
double rangeAt(const std::array<double, 2>& r, double u) { return r[0] + (r[1] - r[0]) * u; }

// The ground coefficients a realisation draws within [ensemble] restitution, friction and
// rolling_resistance, given its uniforms and the seed of the per-cell variability.
void drawGround(const EnsembleSpec& e, double uRestitution, double uFriction, double uRolling,
                std::uint64_t groundSeed, WorldDef& def, RockFallDef& rockFall) {
  if (e.restitution) def.contact.restitutionBodyGround = rangeAt(*e.restitution, uRestitution);
  if (e.friction) def.contact.frictionBodyGround = rangeAt(*e.friction, uFriction);
  const bool drawn = e.restitution || e.friction || e.rollingResistance;
  const bool perCell = rockFall.ground && rockFall.ground->variability > 0;
  if (!rockFall.ground || !(drawn || perCell)) return;
  // Every ground material takes the realisation's values (the class raster is shared), and the
  // per-cell factors the realisation's own seed.
  auto ground = std::make_shared<GroundMap>(*rockFall.ground);
  for (GroundMaterial& m : ground->materials) {
    if (e.restitution) m.restitution = def.contact.restitutionBodyGround;
    if (e.friction) m.friction = def.contact.frictionBodyGround;
    if (e.rollingResistance) m.rollingResistance = rangeAt(*e.rollingResistance, uRolling);
  }
  if (perCell) ground->variabilitySeed = groundSeed;
  rockFall.ground = std::move(ground);
}

}  // namespace

std::uint64_t realisationSeed(std::uint64_t ensembleSeed, std::int64_t index) {
  Prng outer(ensembleSeed);
  Prng inner(outer.next() + static_cast<std::uint64_t>(index));
  return inner.next();
}

void cellsOnSegment(const Heightfield& dem, const Vec3& a, const Vec3& b,
                    std::vector<std::int32_t>& out) {
  // Grid coordinates in which cell (i, j) is [i, i + 1) x [j, j + 1) (Amanatides and Woo's
  // walk: step to whichever cell border the segment reaches first).
  const double ax = (a.x() - dem.x0) / dem.cell + 0.5, ay = (a.y() - dem.y0) / dem.cell + 0.5;
  const double bx = (b.x() - dem.x0) / dem.cell + 0.5, by = (b.y() - dem.y0) / dem.cell + 0.5;
  if (!std::isfinite(ax) || !std::isfinite(ay) || !std::isfinite(bx) || !std::isfinite(by)) return;
  long i = static_cast<long>(std::floor(ax)), j = static_cast<long>(std::floor(ay));
  const long iEnd = static_cast<long>(std::floor(bx)), jEnd = static_cast<long>(std::floor(by));
  const double dx = bx - ax, dy = by - ay;
  const int si = dx > 0 ? 1 : -1, sj = dy > 0 ? 1 : -1;
  // Parameter t (0 at a, 1 at b) of the next x and y border, and per whole cell.
  const double tdx = dx != 0 ? std::abs(1.0 / dx) : INFINITY;
  const double tdy = dy != 0 ? std::abs(1.0 / dy) : INFINITY;
  double tx = dx != 0
                  ? ((si > 0 ? static_cast<double>(i + 1) - ax : ax - static_cast<double>(i)) * tdx)
                  : INFINITY;
  double ty = dy != 0
                  ? ((sj > 0 ? static_cast<double>(j + 1) - ay : ay - static_cast<double>(j)) * tdy)
                  : INFINITY;
  const long maxCells = std::abs(iEnd - i) + std::abs(jEnd - j) + 1;
  for (long k = 0; k < maxCells; ++k) {
    if (i >= 0 && j >= 0 && i < dem.nx && j < dem.ny)
      out.push_back(static_cast<std::int32_t>(j * dem.nx + i));
    if (i == iEnd && j == jEnd) break;
    if (tx < ty) {
      i += si;
      tx += tdx;
    } else {
      j += sj;
      ty += tdy;
    }
  }
}

Ensemble::Ensemble(const SceneSpec& spec) : spec_(spec) {
  VF_ASSERT(spec_.ensemble.has_value());
  const EnsembleSpec& e = *spec_.ensemble;
  base_ = sceneWorldDef(spec_);
  base_.threads = 1;                    // parallel over realisations instead
  VF_ASSERT(base_.terrain != nullptr);  // loadScene requires a heightfield with [ensemble]
  rockFall_ = sceneRockFallDef(spec_, base_.terrain);
  release_ = std::make_shared<const ReleaseSources>(e.releases, base_.terrain, spec_.terrainPath);
  const Heightfield& dem = *base_.terrain;
  lines_ = sceneEvaluationLines(spec_, dem);
  barriers_ = sceneBarriers(spec_, dem);
  for (const Barrier& b : barriers_) barrierPieces_.push_back(barrierPieces(b, dem, spec_.level));
  const auto built = buildSceneShapes(spec_);
  for (const std::string& name : e.shapes) shapes_.push_back(built.at(name).shape);
}

RealisationWorld Ensemble::makeWorld(std::uint64_t seed) const {
  const EnsembleSpec& e = *spec_.ensemble;
  // One generator per realisation drawing the same numbers whatever is switched on, so that
  // varying one thing does not reshuffle the others. The release point gets its own stream
  // (seeded by the first draw): drawing inside an area may take several tries.
  Prng rng(seed);
  const std::uint64_t releaseSeed = rng.next();
  const double uShape = rng.uniform();
  const double u1 = rng.uniform(), u2 = rng.uniform(), u3 = rng.uniform();
  Vec3 uv, uw;
  for (int k = 0; k < 3; ++k) uv[k] = rng.uniform();
  for (int k = 0; k < 3; ++k) uw[k] = rng.uniform();
  const double uRestitution = rng.uniform(), uFriction = rng.uniform(), uRolling = rng.uniform();
  const std::uint64_t groundSeed = rng.next();  // the per-cell variability's ([ground])
  const std::uint64_t sizeSeed = rng.next();    // the rock's volume and density
  const std::uint64_t forestSeed = rng.next();  // the stems' ([forest]); last, as added last

  RealisationWorld out;
  const int shape = drawShape(e, uShape);
  out.shape = shape;

  WorldDef def = base_;
  RockFallDef rockFall = rockFall_;
  rockFall.forestSeed = forestSeed;
  drawGround(e, uRestitution, uFriction, uRolling, groundSeed, def, rockFall);

  int source = 0;
  const Point2 xy = release_->draw(releaseSeed, &source);
  BodyDef body;
  body.shape = sized(shapes_[static_cast<std::size_t>(shape)], source, sizeSeed);
  body.orientation = e.randomOrientation ? uniformRotation(u1, u2, u3) : Quat::Identity();
  // Placed on the surface at (x, y); addBody lifts it to drop_height above what lies below.
  body.position = Vec3(xy[0], xy[1], base_.terrain->heightAt(xy[0], xy[1]));
  body.velocity = e.velocityMin + (e.velocityMax - e.velocityMin).cwiseProduct(uv);
  body.angularVelocity =
      e.angularVelocityMin + (e.angularVelocityMax - e.angularVelocityMin).cwiseProduct(uw);
  body.dropHeight = e.dropHeight;
  out.world = std::make_unique<World>(std::move(def));
  out.rockFall = &attachRockFall(*out.world, std::move(rockFall));
  out.world->addBody(body);
  out.barriers = attachBarriers(*out.world, barriers_, barrierPieces_);
  return out;
}

std::shared_ptr<const Shape> Ensemble::sized(const std::shared_ptr<const Shape>& shape, int source,
                                             std::uint64_t seed) const {
  const EnsembleSpec& e = *spec_.ensemble;
  const std::optional<VolumeSpec>& own = e.releases[static_cast<std::size_t>(source)].volume;
  const std::optional<VolumeSpec>& volume = own ? own : e.volume;
  if (!volume && !e.density) return shape;
  Prng rng(seed);
  const double uVolume = rng.uniform(), uDensity = rng.uniform();
  const double v = volume ? volumeAt(*volume, uVolume) : shape->volume;
  const double density = e.density
                             ? (*e.density)[0] + ((*e.density)[1] - (*e.density)[0]) * uDensity
                             : shape->mass / shape->volume;
  return resizedShape(*shape, v, density);
}

RealisationResult Ensemble::run(std::int64_t index, std::uint64_t seed, bool keepPath,
                                const std::function<bool()>& stop) const {
  RealisationResult r;
  r.index = index;
  r.seed = seed;
  const RealisationWorld made = makeWorld(seed);
  World& w = *made.world;
  const RockFall& rockFall = *made.rockFall;
  r.shape = made.shape;
  const Heightfield& dem = *base_.terrain;
  CellMaxima cells(dem, r.cells);
  // Crossings of the evaluation lines on the step states (sim/ground/evaluation_lines.h).
  CrossingRecorder lines(lines_);
  lines.observe(w, index);
  SampleValues before = sample(w, dem);
  Vec3 xBefore = w.state(0).x;
  r.maxEnergy = before.energy;
  cells.add(xBefore, xBefore, before);
  if (keepPath) r.path.push_back(PathPoint{w.time(), xBefore});
  const double duration = spec_.duration;
  r.complete = true;
  while (w.nextStepEnd() <= duration + kTimeTolerance) {
    if (stop && stop()) {
      r.complete = false;
      break;
    }
    try {
      w.stepNext();
    } catch (const RunawayError& e) {
      // The whole ensemble stops (exit 1), naming the realisation so that `--only` reruns it.
      throw std::runtime_error("realisation " + std::to_string(index) + " (seed " +
                               std::to_string(seed) + "): " + e.what());
    }
    lines.observe(w, index);
    const SampleValues after = sample(w, dem);
    const Vec3 x = w.state(0).x;
    const SampleValues most{std::max(before.energy, after.energy),
                            std::max(before.height, after.height),
                            std::max(before.speed, after.speed)};
    cells.add(xBefore, x, most);
    r.maxEnergy = std::max(r.maxEnergy, after.energy);
    if (keepPath) r.path.push_back(PathPoint{w.time(), x});
    before = after;
    xBefore = x;
    if (rockFall.outcomes()[0].state != RockState::kMoving) break;  // stopped, left or buried
  }
  std::sort(r.cells.begin(), r.cells.end(),
            [](const CellPassage& a, const CellPassage& b) { return a.cell < b.cell; });
  readOutcome(w, rockFall, r);
  r.crossings = lines.crossings();
  if (made.barriers) r.barriers = made.barriers->results();
  return r;
}

std::vector<std::vector<Point2>> Ensemble::releaseAreas() const { return release_->outlines(); }

namespace {

// Slots of complete realisations, filled by the workers and handed to the calling thread.
class FinishedQueue {
 public:
  void push(std::size_t k) {
    std::lock_guard<std::mutex> lock(mutex_);
    slots_.push_back(k);
  }
  std::vector<std::size_t> take() {
    std::lock_guard<std::mutex> lock(mutex_);
    std::vector<std::size_t> out;
    out.swap(slots_);
    return out;
  }

 private:
  std::mutex mutex_;
  std::vector<std::size_t> slots_;
};

}  // namespace

std::vector<RealisationResult> runRealisations(
    const Ensemble& ensemble, const std::vector<std::int64_t>& indices, std::uint64_t ensembleSeed,
    int jobs, bool keepPaths, const std::function<void(int)>& progress,
    const std::function<bool()>& stop,
    const std::function<void(const RealisationResult&)>& onResult) {
  std::vector<RealisationResult> results(indices.size());
  for (std::size_t k = 0; k < indices.size(); ++k) results[k].index = indices[k];
  std::atomic<std::size_t> next{0};
  std::atomic<int> done{0};
  const int threads = std::max(1, std::min<int>(jobs, static_cast<int>(indices.size())));
  std::atomic<int> running{threads};
  std::mutex failure;
  std::exception_ptr error;
  FinishedQueue finished;
  // Each worker takes the next index; results land at their own slot, so the order of the
  // results never depends on which thread ran what.
  const auto work = [&] {
    for (;;) {
      const std::size_t k = next.fetch_add(1);
      if (k >= indices.size() || (stop && stop())) break;
      try {
        results[k] =
            ensemble.run(indices[k], realisationSeed(ensembleSeed, indices[k]), keepPaths, stop);
      } catch (...) {
        std::lock_guard<std::mutex> lock(failure);
        if (!error) error = std::current_exception();
        next.store(indices.size());
        break;
      }
      if (results[k].complete) finished.push(k);
      done.fetch_add(1);
    }
    running.fetch_sub(1);
  };
  // The calling thread hands over finished results (in the order they finish) and reports
  // progress while the workers run, so that a journal or MPI sees only this thread.
  const auto handOver = [&] {
    if (!onResult) return;
    for (std::size_t k : finished.take()) onResult(results[k]);
  };
  std::vector<std::thread> workers;
  for (int t = 0; t < threads; ++t) workers.emplace_back(work);
  while (running.load() > 0) {
    handOver();
    if (progress) progress(done.load());
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  for (std::thread& w : workers) w.join();
  handOver();
  if (error) std::rethrow_exception(error);
  if (progress) progress(done.load());
  return results;
}

// --- serialisation (MPI, journal)
// ------------------------------------------------------------------

namespace {

template <typename T>
void put(std::string& s, const T& v) {
  static_assert(std::is_trivially_copyable_v<T>);
  s.append(reinterpret_cast<const char*>(&v), sizeof v);
}

template <typename T>
T take(const std::string& s, std::size_t& pos) {
  T v;
  if (pos + sizeof v > s.size()) throw InputError("", "truncated ensemble results");
  std::memcpy(&v, s.data() + pos, sizeof v);
  pos += sizeof v;
  return v;
}

void putVec(std::string& s, const Vec3& v) {
  for (int k = 0; k < 3; ++k) put(s, v[k]);
}

Vec3 takeVec(const std::string& s, std::size_t& pos) {
  Vec3 v;
  for (int k = 0; k < 3; ++k) v[k] = take<double>(s, pos);
  return v;
}

// A count of items of `itemBytes` each that must fit in the bytes left.
std::size_t takeCount(const std::string& s, std::size_t& pos, std::size_t itemBytes) {
  const std::uint64_t n = take<std::uint64_t>(s, pos);
  if (n > (s.size() - pos) / itemBytes) throw InputError("", "truncated ensemble results");
  return static_cast<std::size_t>(n);
}

// A serialised LineCrossing: line, direction, rock, time, two energies, height, point, velocity.
constexpr std::size_t kCrossingBytes = 4 + 4 + 8 + 4 * 8 + 6 * 8;
// A serialised BarrierResult: hits, stopped, passed, max energy, failed.
constexpr std::size_t kBarrierBytes = 3 * 8 + 8 + 1;

}  // namespace

void serializeResult(const RealisationResult& r, std::string& s) {
  put(s, r.index);
  put(s, r.seed);
  put<std::uint8_t>(s, r.complete ? 1 : 0);
  put<std::int32_t>(s, r.shape);
  putVec(s, r.release);
  putVec(s, r.end);
  put(s, r.endTime);
  put<std::int32_t>(s, static_cast<std::int32_t>(r.state));
  for (double v :
       {r.runout, r.reachAngle, r.maxSpeed, r.maxEnergy, r.maxJumpHeight, r.volume, r.mass})
    put(s, v);
  put<std::int32_t>(s, r.treeHits);
  put(s, r.treeEnergy);
  put(s, r.steps);
  put(s, r.checksum);
  put<std::uint64_t>(s, r.cells.size());
  for (const CellPassage& c : r.cells) {
    put(s, c.cell);
    put(s, c.energy);
    put(s, c.height);
    put(s, c.speed);
  }
  put<std::uint64_t>(s, r.path.size());
  for (const PathPoint& p : r.path) {
    put(s, p.time);
    putVec(s, p.x);
  }
  put<std::uint64_t>(s, r.crossings.size());
  for (const LineCrossing& c : r.crossings) {
    put(s, c.line);
    put(s, c.direction);
    put(s, c.rock);
    for (double v : {c.time, c.translationalEnergy, c.rotationalEnergy, c.height}) put(s, v);
    putVec(s, c.point);
    putVec(s, c.velocity);
  }
  put<std::uint64_t>(s, r.barriers.size());
  for (const BarrierResult& b : r.barriers) {
    for (std::int64_t n : {b.hits, b.stopped, b.passed}) put(s, n);
    put(s, b.maxEnergy);
    put<std::uint8_t>(s, b.failed ? 1 : 0);
  }
}

RealisationResult deserializeResult(const std::string& s, std::size_t& pos) {
  RealisationResult r;
  r.index = take<std::int64_t>(s, pos);
  r.seed = take<std::uint64_t>(s, pos);
  r.complete = take<std::uint8_t>(s, pos) != 0;
  r.shape = take<std::int32_t>(s, pos);
  r.release = takeVec(s, pos);
  r.end = takeVec(s, pos);
  r.endTime = take<double>(s, pos);
  r.state = static_cast<RockState>(take<std::int32_t>(s, pos));
  r.runout = take<double>(s, pos);
  r.reachAngle = take<double>(s, pos);
  r.maxSpeed = take<double>(s, pos);
  r.maxEnergy = take<double>(s, pos);
  r.maxJumpHeight = take<double>(s, pos);
  r.volume = take<double>(s, pos);
  r.mass = take<double>(s, pos);
  r.treeHits = take<std::int32_t>(s, pos);
  r.treeEnergy = take<double>(s, pos);
  r.steps = take<std::int64_t>(s, pos);
  r.checksum = take<std::uint64_t>(s, pos);
  // Counts are checked against the bytes left before anything is allocated: a damaged count
  // is an error, not a huge allocation.
  r.cells.resize(takeCount(s, pos, 28));
  for (CellPassage& c : r.cells) {
    c.cell = take<std::int32_t>(s, pos);
    c.energy = take<double>(s, pos);
    c.height = take<double>(s, pos);
    c.speed = take<double>(s, pos);
  }
  r.path.resize(takeCount(s, pos, 32));
  for (PathPoint& p : r.path) {
    p.time = take<double>(s, pos);
    p.x = takeVec(s, pos);
  }
  r.crossings.resize(takeCount(s, pos, kCrossingBytes));
  for (LineCrossing& c : r.crossings) {
    c.line = take<std::int32_t>(s, pos);
    c.direction = take<std::int32_t>(s, pos);
    c.rock = take<std::int64_t>(s, pos);
    c.time = take<double>(s, pos);
    c.translationalEnergy = take<double>(s, pos);
    c.rotationalEnergy = take<double>(s, pos);
    c.height = take<double>(s, pos);
    c.point = takeVec(s, pos);
    c.velocity = takeVec(s, pos);
  }
  r.barriers.resize(takeCount(s, pos, kBarrierBytes));
  for (BarrierResult& b : r.barriers) {
    b.hits = take<std::int64_t>(s, pos);
    b.stopped = take<std::int64_t>(s, pos);
    b.passed = take<std::int64_t>(s, pos);
    b.maxEnergy = take<double>(s, pos);
    b.failed = take<std::uint8_t>(s, pos) != 0;
  }
  return r;
}

std::string serializeResults(const std::vector<RealisationResult>& results) {
  std::string s;
  put<std::uint64_t>(s, results.size());
  for (const RealisationResult& r : results) serializeResult(r, s);
  return s;
}

std::vector<RealisationResult> deserializeResults(const std::string& s) {
  std::size_t pos = 0;
  const std::uint64_t n = take<std::uint64_t>(s, pos);
  std::vector<RealisationResult> out;
  for (std::uint64_t k = 0; k < n; ++k) out.push_back(deserializeResult(s, pos));
  return out;
}

}  // namespace vf

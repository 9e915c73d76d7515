// Rocks meeting stems after each step (the model and its sources: forest_law.h, forest.h).
#include "sim/ground/forest_law.h"

#include <cmath>
#include <numbers>

#include "sim/core/hash.h"
#include "sim/shape/shape.h"

namespace vf {

namespace {

// The diameter of the sphere of the rock's volume, m: the size the stand's band is swept by.
double rockDiameter(const BodyInfo& b) {
  return std::cbrt(6.0 * b.shape->volume / std::numbers::pi);
}

// Kinetic energy, J: translation P^2 / 2M and spin w.L / 2.
double kineticEnergy(const BodyInfo& b, const BodyState& y) {
  return 0.5 * b.invMass * y.P.squaredNorm() + 0.5 * angularVelocityOf(b, y).dot(y.L);
}

// Whether the body's centre is low enough to meet the stems.
bool underCrowns(const Forest& forest, const Vec3& x) {
  if (!forest.stemHeight) return true;
  const double ground = forest.grid->heightAt(x.x(), x.y());
  return std::isnan(ground) || x.z() - ground < *forest.stemHeight;
}

}  // namespace

int ForestLaw::afterStep(const Forest& forest, std::uint64_t seed,
                         const std::vector<BodyInfo>& bodies, std::vector<BodyState>& states) {
  int hitsNow = 0;
  while (tracks_.size() < bodies.size()) {
    Hasher h;  // one stream per (seed, body): no body's draws depend on another's
    h.add(seed);
    h.add(static_cast<std::uint64_t>(tracks_.size()));
    tracks_.push_back(Track{false, Vec3::Zero(), Prng(h.value()), TreeHits{}});
  }
  for (std::size_t i = 0; i < bodies.size(); ++i) {
    const BodyInfo& b = bodies[i];
    Track& t = tracks_[i];
    if (!b.moves()) {
      t.seen = false;  // released, woken or put back later: start a new path there
      continue;
    }
    BodyState& y = states[i];
    const Vec3 from = t.last;
    const bool had = t.seen;
    t.seen = true;
    t.last = y.x;
    if (!had) continue;
    const Vec3 mid = 0.5 * (from + y.x);
    Forest::Stand stand;
    if (!forest.standAt(mid.x(), mid.y(), stand) || !underCrowns(forest, mid)) continue;
    const double s = (y.x - from).head<2>().norm();
    const double p = stemHitProbability(stand.stemsPerHectare, stand.dbhCm, rockDiameter(b), s);
    if (!(p > 0) || !(t.rng.uniform() < p)) continue;
    const double k = kineticEnergy(b, y);
    const double e = std::min(stemEnergy(stand.dbhCm, stand.speciesFactor), k);
    const double keep = k > 0 ? std::sqrt(std::max(0.0, 1.0 - e / k)) : 0.0;
    y.P *= keep;
    y.L *= keep;
    ++t.hits.hits;
    t.hits.absorbed += e;
    ++hitsNow;
  }
  return hitsNow;
}

TreeHits ForestLaw::hits(int id) const {
  return static_cast<std::size_t>(id) < tracks_.size() ? tracks_[static_cast<std::size_t>(id)].hits
                                                       : TreeHits{};
}

}  // namespace vf

#include "sim/ground/evaluation_lines.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>

#include "sim/core/percentile.h"

namespace vf {
namespace {

double cross2(double ax, double ay, double bx, double by) { return ax * by - ay * bx; }

// The ground vertically under (x, y): the terrain, else the floor plane, else NaN.
double groundUnder(const WorldDef& def, double x, double y) {
  double h = std::numeric_limits<double>::quiet_NaN();
  if (def.terrain) h = def.terrain->heightAt(x, y);
  if (std::isnan(h) && def.groundHeight) h = *def.groundHeight;
  return h;
}

}  // namespace

void curtainHits(const std::vector<std::array<double, 2>>& line, const Vec3& a, const Vec3& b,
                 std::vector<CurtainHit>& out) {
  const double dx = b.x() - a.x(), dy = b.y() - a.y();
  for (std::size_t k = 0; k + 1 < line.size(); ++k) {
    const double ex = line[k + 1][0] - line[k][0], ey = line[k + 1][1] - line[k][1];
    const double denom = cross2(dx, dy, ex, ey);
    if (denom == 0) continue;  // parallel (or a standing rock): no crossing
    const double qx = line[k][0] - a.x(), qy = line[k][1] - a.y();
    const double s = cross2(qx, qy, ex, ey) / denom;  // along a -> b
    const double u = cross2(qx, qy, dx, dy) / denom;  // along the line segment
    const bool last = k + 2 == line.size();
    if (!(s > 0 && s <= 1) || !(u >= 0 && (u < 1 || (last && u <= 1)))) continue;
    // d x e > 0: the line's direction is counter-clockwise from the path's, so the path runs
    // from the line's left to its right.
    out.push_back(CurtainHit{s, denom > 0 ? 1 : -1});
  }
}

void CrossingRecorder::observe(const World& w, std::int64_t rockOfBody) {
  last_.resize(static_cast<std::size_t>(w.bodyCount()));
  const double t = w.time();
  for (int i = 0; i < w.bodyCount(); ++i) {
    StepState& before = last_[static_cast<std::size_t>(i)];
    if (!w.isActive(i) || w.isStatic(i)) {
      before.valid = false;
      continue;
    }
    StepState now;
    now.valid = true;
    now.time = t;
    now.x = w.state(i).x;
    now.v = w.velocity(i);
    now.rotationalEnergy = 0.5 * w.state(i).L.dot(w.angularVelocity(i));
    if (before.valid && now.time > before.time) {
      const std::size_t first = crossings_.size();
      for (std::size_t l = 0; l < lines_.size(); ++l) {
        hits_.clear();
        curtainHits(lines_[l].points, before.x, now.x, hits_);
        for (const CurtainHit& h : hits_) {
          LineCrossing c;
          c.line = static_cast<std::int32_t>(l);
          c.rock = rockOfBody >= 0 ? rockOfBody : i;
          c.time = before.time + h.s * (now.time - before.time);
          c.point = before.x + h.s * (now.x - before.x);
          c.velocity = before.v + h.s * (now.v - before.v);
          c.translationalEnergy = 0.5 * w.shape(i).mass * c.velocity.squaredNorm();
          c.rotationalEnergy =
              before.rotationalEnergy + h.s * (now.rotationalEnergy - before.rotationalEnergy);
          c.height = c.point.z() - groundUnder(w.def(), c.point.x(), c.point.y());
          c.direction = h.direction;
          crossings_.push_back(c);
        }
      }
      // One body's crossings of one step in time order (lines in order at equal times).
      std::stable_sort(
          crossings_.begin() + static_cast<std::ptrdiff_t>(first), crossings_.end(),
          [](const LineCrossing& p, const LineCrossing& q) { return p.time < q.time; });
    }
    before = now;
  }
}

std::vector<LineSummary> summariseLines(const std::vector<EvaluationLine>& lines,
                                        const std::vector<LineCrossing>& crossings,
                                        std::int64_t rocks) {
  std::vector<LineSummary> out(lines.size());
  for (std::size_t l = 0; l < lines.size(); ++l) {
    LineSummary& s = out[l];
    s.name = lines[l].name;
    s.rocks = rocks;
    std::vector<double> energy, height;
    std::set<std::int64_t> crossed;
    for (const LineCrossing& c : crossings) {
      if (c.line != static_cast<std::int32_t>(l)) continue;
      ++s.crossings;
      crossed.insert(c.rock);
      energy.push_back(c.energy());
      if (!std::isnan(c.height)) height.push_back(c.height);
    }
    s.rocksCrossing = static_cast<std::int64_t>(crossed.size());
    s.probability = rocks > 0 ? static_cast<double>(s.rocksCrossing) / rocks : 0.0;
    std::sort(energy.begin(), energy.end());
    std::sort(height.begin(), height.end());
    const double nan = std::numeric_limits<double>::quiet_NaN();
    for (std::size_t k = 0; k < kLinePercentiles.size(); ++k) {
      s.energy[k] = energy.empty()
                        ? nan
                        : nearestRankPercentile(energy.data(), energy.size(), kLinePercentiles[k]);
      s.height[k] = height.empty()
                        ? nan
                        : nearestRankPercentile(height.data(), height.size(), kLinePercentiles[k]);
    }
  }
  return out;
}

}  // namespace vf

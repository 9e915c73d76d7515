#include "sim/ground/barriers.h"

#include <algorithm>
#include <cmath>

#include "sim/geometry/tri_mesh.h"

namespace vf {
namespace {

// A closed box a x b x c centred at the origin, counter-clockwise outward triangles.
TriMesh box(double a, double b, double c) {
  TriMesh m;
  for (int i = 0; i < 8; ++i)
    m.vertices.push_back(
        Vec3((i & 1 ? 0.5 : -0.5) * a, (i & 2 ? 0.5 : -0.5) * b, (i & 4 ? 0.5 : -0.5) * c));
  m.triangles = {{0, 2, 3}, {0, 3, 1}, {4, 5, 7}, {4, 7, 6}, {0, 1, 5}, {0, 5, 4},
                 {2, 6, 7}, {2, 7, 3}, {0, 4, 6}, {0, 6, 2}, {1, 3, 7}, {1, 7, 5}};
  return m;
}

// The lowest ground along a -> b (sampled at a tenth of a cell), and the ground at its middle.
std::pair<double, double> groundAlong(const Heightfield& t, const Vec3& a, const Vec3& b) {
  const int n = std::max(2, static_cast<int>(std::ceil((b - a).norm() / (0.1 * t.cell))));
  double lowest = INFINITY;
  for (int k = 0; k <= n; ++k) {
    const Vec3 p = a + (b - a) * (static_cast<double>(k) / n);
    const double h = t.heightAt(p.x(), p.y());
    if (!std::isnan(h)) lowest = std::min(lowest, h);
  }
  const Vec3 m = 0.5 * (a + b);
  return {lowest, t.heightAt(m.x(), m.y())};
}

double kineticEnergy(const World& w, int id) {
  return 0.5 * w.shape(id).mass * w.velocity(id).squaredNorm() +
         0.5 * w.state(id).L.dot(w.angularVelocity(id));
}

}  // namespace

std::vector<BarrierPiece> barrierPieces(const Barrier& barrier, const Heightfield& terrain,
                                        int level) {
  std::vector<BarrierPiece> out;
  for (std::size_t k = 0; k + 1 < barrier.points.size(); ++k) {
    const Vec3 a(barrier.points[k][0], barrier.points[k][1], 0);
    const Vec3 b(barrier.points[k + 1][0], barrier.points[k + 1][1], 0);
    const double length = (b - a).norm();
    if (!(length > 0)) continue;
    const int n = std::max(1, static_cast<int>(std::ceil(length / barrier.height)));
    const Quat q(Eigen::AngleAxisd(std::atan2(b.y() - a.y(), b.x() - a.x()), Vec3::UnitZ()));
    for (int i = 0; i < n; ++i) {
      const Vec3 p0 = a + (b - a) * (static_cast<double>(i) / n);
      const Vec3 p1 = a + (b - a) * (static_cast<double>(i + 1) / n);
      const auto [lowest, middle] = groundAlong(terrain, p0, p1);
      const double bottom = lowest - kBarrierEmbed, top = middle + barrier.height;
      BarrierPiece piece;
      piece.shape = makeShape(barrier.name, box(length / n, barrier.thickness, top - bottom),
                              Vec3::Ones(), 1000, level);
      piece.position = Vec3(0.5 * (p0.x() + p1.x()), 0.5 * (p0.y() + p1.y()), 0.5 * (bottom + top));
      piece.orientation = q;
      out.push_back(std::move(piece));
    }
  }
  return out;
}

BarrierMonitor::BarrierMonitor(std::vector<Barrier> barriers, std::vector<std::vector<int>> bodies)
    : barriers_(std::move(barriers)), bodies_(std::move(bodies)), results_(barriers_.size()) {
  for (std::size_t b = 0; b < bodies_.size(); ++b)
    for (int id : bodies_[b]) {
      if (static_cast<int>(barrierOf_.size()) <= id) barrierOf_.resize(id + 1, -1);
      barrierOf_[static_cast<std::size_t>(id)] = static_cast<int>(b);
    }
}

BarrierMonitor BarrierMonitor::build(World& world, const std::vector<Barrier>& barriers,
                                     const std::vector<std::vector<BarrierPiece>>& pieces) {
  std::vector<std::vector<int>> bodies(barriers.size());
  for (std::size_t b = 0; b < barriers.size(); ++b)
    for (const BarrierPiece& p : pieces[b]) {
      BodyDef d;
      d.shape = p.shape;
      d.position = p.position;
      d.orientation = p.orientation;
      d.isStatic = true;
      bodies[b].push_back(world.addBody(d));
    }
  return BarrierMonitor(barriers, std::move(bodies));
}

void BarrierMonitor::observe(World& w) {
  if (barriers_.empty()) return;
  // The rule at each first contact of a rock with a barrier in the last step, in contact order.
  const auto barrierOf = [&](int id) {
    return id >= 0 && id < static_cast<int>(barrierOf_.size()) ? barrierOf_[id] : -1;
  };
  if (!last_.empty())
    for (const Contact& c : w.contacts()) {
      const int ba = barrierOf(c.a), bb = barrierOf(c.b);
      if ((ba < 0) == (bb < 0)) continue;  // not a rock against a barrier
      const int barrier = ba >= 0 ? ba : bb, rock = ba >= 0 ? c.b : c.a;
      if (rock < 0 || rock >= static_cast<int>(last_.size()) || !last_[rock].valid) continue;
      const std::pair<int, int> key{rock, barrier};
      if (std::find(handled_.begin(), handled_.end(), key) != handled_.end()) continue;
      handled_.push_back(key);
      BarrierResult& r = results_[static_cast<std::size_t>(barrier)];
      const Motion& m = last_[static_cast<std::size_t>(rock)];
      ++r.hits;
      r.maxEnergy = std::max(r.maxEnergy, m.energy);
      const double capacity = barriers_[static_cast<std::size_t>(barrier)].capacity;
      if (m.energy <= capacity) {
        ++r.stopped;  // the net takes it all: the rock rests against it
        w.setMotion(rock, Vec3::Zero(), Vec3::Zero());
      } else {
        // The barrier breaks: it is gone, and the rock goes on with its motion at the hit
        // scaled so that its kinetic energy is what the barrier could not take.
        ++r.passed;
        r.failed = true;
        for (int id : bodies_[static_cast<std::size_t>(barrier)]) w.deactivate(id);
        const double f = std::sqrt((m.energy - capacity) / m.energy);
        w.setMotion(rock, f * m.v, f * m.w);
      }
    }
  last_.resize(static_cast<std::size_t>(w.bodyCount()));
  for (int i = 0; i < w.bodyCount(); ++i) {
    Motion& m = last_[static_cast<std::size_t>(i)];
    m.valid = w.isActive(i) && !w.isStatic(i);
    if (!m.valid) continue;
    m.v = w.velocity(i);
    m.w = w.angularVelocity(i);
    m.energy = kineticEnergy(w, i);
  }
}

}  // namespace vf

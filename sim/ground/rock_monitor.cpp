// Rock fall bookkeeping after each step (see rock_monitor.h).
//
// Why a body below the surface is pushed out rather than left to the solver: the impulse solve
// has no position correction, so a body whose centre is under the heightfield (rolled beneath
// it from a catch plane, or placed there) meets leaf contacts whose normals all point up out
// of the terrain with depths of metres, and can be thrown out at 45,000 m/s. A body
// partly below (centre under the surface, some point above it) is moved along the surface
// normal until no vertex is below, and its velocity into the surface removed; a body wholly
// below is stopped where it is. Both are reported with the body and the time.
#include "sim/ground/rock_monitor.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "sim/shape/heightfield.h"
#include "sim/shape/shape.h"

namespace vf {

const char* rockStateName(RockState s) {
  switch (s) {
    case RockState::kMoving:
      return "moving";
    case RockState::kStopped:
      return "stopped";
    case RockState::kLeft:
      return "left";
    case RockState::kBuried:
      return "buried";
  }
  return "?";
}

double RockOutcome::reachAngleDegrees() const {
  const double run = runout();
  if (!(run > 0)) return 90.0;
  return std::atan2(release.z() - end.z(), run) * 180.0 / M_PI;
}

void RockMonitor::configure(TerrainEdge edge, RestCriterion rest, const Heightfield* terrain,
                            std::optional<double> plane, const Vec3& gravity) {
  edge_ = edge == TerrainEdge::kAuto ? (plane ? TerrainEdge::kAuto : TerrainEdge::kRemove) : edge;
  rest_ = rest;
  terrain_ = terrain;
  plane_ = plane;
  gravity_ = gravity;
}

double RockMonitor::groundAtHeight(double h) const {
  if (!std::isnan(h)) return plane_ ? std::max(h, *plane_) : h;
  return plane_ ? *plane_ : NAN;
}

void RockMonitor::onRelease(int id, double time, std::vector<BodyInfo>& bodies,
                            std::vector<BodyState>& states) {
  const BodyState& y = states[static_cast<std::size_t>(id)];
  if (static_cast<int>(rocks_.size()) <= id) {
    rocks_.resize(static_cast<std::size_t>(id) + 1);
    previous_.resize(rocks_.size(), Vec3::Zero());
    nextPathTime_.resize(rocks_.size(), 0.0);
  }
  RockOutcome& r = rocks_[static_cast<std::size_t>(id)];
  r = RockOutcome();
  r.released = true;
  r.release = y.x;
  r.releaseTime = time;
  r.end = y.x;
  r.endTime = time;
  r.path.push_back(y.x);
  previous_[static_cast<std::size_t>(id)] = y.x;
  nextPathTime_[static_cast<std::size_t>(id)] = time + kPathInterval;
  // A body released below the surface is pushed out (or stopped) before its first step, so no
  // step ever solves contacts metres deep (and the run guard sees no energy from them).
  if (terrain_) {
    double h = terrain_->heightAt(y.x.x(), y.x.y());
    resolveBelowSurface(id, time, bodies, states, h);
  }
}

void RockMonitor::finish(int id, RockState state, const Vec3& where, double time,
                         const std::string& why, std::vector<BodyInfo>& bodies,
                         std::vector<BodyState>& states) {
  RockOutcome& r = rocks_[static_cast<std::size_t>(id)];
  r.state = state;
  r.end = where;
  r.endTime = time;
  r.message = why;
  r.path.push_back(where);
  messages_.push_back(why);
  // Out of the simulation for good: inactive, and never released again.
  bodies[static_cast<std::size_t>(id)].active = false;
  bodies[static_cast<std::size_t>(id)].releaseTime = INFINITY;
  states[static_cast<std::size_t>(id)].P.setZero();
  states[static_cast<std::size_t>(id)].L.setZero();
}

bool RockMonitor::resolveBelowSurface(int i, double time, std::vector<BodyInfo>& bodies,
                                      std::vector<BodyState>& states, double& h) {
  BodyState& y = states[static_cast<std::size_t>(i)];
  if (std::isnan(h) || y.x.z() >= h) return false;
  const Shape& shape = *bodies[static_cast<std::size_t>(i)].shape;
  const Mat3 R = y.q.toRotationMatrix();
  // Below the surface: how deep is its deepest vertex, and is any vertex above?
  double deepest = 0, highestAbove = -INFINITY;
  for (const Vec3& v : shape.mesh.vertices) {
    const Vec3 p = y.x + R * v;
    const double hv = terrain_->heightAt(p.x(), p.y());
    if (std::isnan(hv)) continue;
    deepest = std::max(deepest, hv - p.z());
    highestAbove = std::max(highestAbove, p.z() - hv);
  }
  char buf[320];
  if (highestAbove <= 0) {
    std::snprintf(buf, sizeof buf,
                  "body %d is wholly below the terrain surface at t = %.4f s, at (%.3f, "
                  "%.3f, %.3f) m: stopped there",
                  i, time, y.x.x(), y.x.y(), y.x.z());
    finish(i, RockState::kBuried, y.x, time, buf, bodies, states);
    return true;
  }
  const Vec3 nrm = terrain_->normalAt(y.x.x(), y.x.y());
  // Along the normal by deepest * n.z: for a locally planar surface that lifts the
  // deepest vertex exactly onto it.
  y.x += (deepest * nrm.z()) * nrm;
  h = terrain_->heightAt(y.x.x(), y.x.y());
  const double vn = y.P.dot(nrm);
  if (vn < 0) y.P -= vn * nrm;
  std::snprintf(buf, sizeof buf,
                "body %d was partly below the terrain surface at t = %.4f s: pushed out "
                "%.3f m along the surface normal",
                i, time, deepest * nrm.z());
  messages_.push_back(buf);
  return false;
}

int RockMonitor::afterStep(double time, std::vector<BodyInfo>& bodies,
                           std::vector<BodyState>& states) {
  int finished = 0;
  const int n = static_cast<int>(bodies.size());
  for (int i = 0; i < n; ++i) {
    BodyInfo& b = bodies[static_cast<std::size_t>(i)];
    if (!b.dynamic() || i >= static_cast<int>(rocks_.size()) || !rocks_[i].released) continue;
    BodyState& y = states[static_cast<std::size_t>(i)];
    RockOutcome& r = rocks_[static_cast<std::size_t>(i)];
    // A sleeping rock (solve/sleep.h) is frozen at rest: nothing to check or record but its
    // rest time, so that it comes to count as stopped (else a run with sleep on would never
    // end on "all_at_rest"), and it costs next to nothing.
    if (b.sleeping) {
      updateRest(r, true, y.x, time);
      continue;
    }
    const Shape& shape = *b.shape;
    const Mat3 R = y.q.toRotationMatrix();

    // The terrain's height under the centre, looked up once and kept while the centre stays.
    double h = terrain_ ? terrain_->heightAt(y.x.x(), y.x.y()) : NAN;
    // Edges and holes: the centre of mass over no terrain data.
    if (terrain_ && std::isnan(h) && edge_ != TerrainEdge::kAuto) {
      const bool outside = y.x.x() < terrain_->x0 || y.x.y() < terrain_->y0 ||
                           y.x.x() > terrain_->x0 + (terrain_->nx - 1) * terrain_->cell ||
                           y.x.y() > terrain_->y0 + (terrain_->ny - 1) * terrain_->cell;
      const char* where = outside ? "left the terrain grid" : "entered a NODATA hole";
      if (edge_ == TerrainEdge::kWall) {
        // Back to where it last was over ground; horizontal velocity reflected (no loss).
        y.x.head<2>() = previous_[static_cast<std::size_t>(i)].head<2>();
        y.P.head<2>() = -y.P.head<2>();
        h = terrain_->heightAt(y.x.x(), y.x.y());
      } else {
        char buf[320];
        std::snprintf(buf, sizeof buf, "body %d %s at t = %.4f s, at (%.3f, %.3f, %.3f) m", i,
                      where, time, y.x.x(), y.x.y(), y.x.z());
        if (edge_ == TerrainEdge::kStop && stopReason_.empty()) stopReason_ = buf;
        finish(i, RockState::kLeft, y.x, time, buf, bodies, states);
        ++finished;
        continue;
      }
    }
    if (terrain_) {
      if (resolveBelowSurface(i, time, bodies, states, h)) {
        ++finished;
        continue;
      }
      if (!std::isnan(h)) previous_[static_cast<std::size_t>(i)] = y.x;
    }

    // Maxima, path, rest.
    const double m = shape.mass;
    const Vec3 v = velocityOf(b, y);
    const Vec3 w = angularVelocityOf(b, y);
    r.maxSpeed = std::max(r.maxSpeed, v.norm());
    r.maxTranslationalEnergy = std::max(r.maxTranslationalEnergy, 0.5 * m * v.squaredNorm());
    r.maxRotationalEnergy = std::max(r.maxRotationalEnergy, 0.5 * y.L.dot(w));
    const double g = groundAtHeight(h);
    if (!std::isnan(g)) {
      double lowest = INFINITY;
      for (const Vec3& p : shape.mesh.vertices) lowest = std::min(lowest, (R * p).z());
      r.maxJumpHeight = std::max(r.maxJumpHeight, y.x.z() + lowest - g);
    }
    if (time >= nextPathTime_[static_cast<std::size_t>(i)] - 1e-9) {
      r.path.push_back(y.x);
      nextPathTime_[static_cast<std::size_t>(i)] += kPathInterval;
    }
    updateRest(r, v.norm() < rest_.speed && w.norm() * 0.5 * shape.diameter < rest_.speed, y.x,
               time);
  }
  return finished;
}

void RockMonitor::updateRest(RockOutcome& r, bool slow, const Vec3& x, double time) const {
  if (!slow) {
    r.restSince = -1;
    if (r.state == RockState::kStopped) r.state = RockState::kMoving;  // knocked on
  } else if (r.restSince < 0) {
    r.restSince = time;
  } else if (r.state == RockState::kMoving && time - r.restSince >= rest_.time - 1e-9) {
    r.state = RockState::kStopped;
  }
  if (r.state == RockState::kMoving || r.state == RockState::kStopped) {
    r.end = x;
    r.endTime = r.state == RockState::kStopped ? r.restSince : time;
  }
}

void RockMonitor::countBounce(int id) {
  if (id >= 0 && id < static_cast<int>(rocks_.size()))
    ++rocks_[static_cast<std::size_t>(id)].bounces;
}

bool RockMonitor::allSettled(const std::vector<BodyInfo>& bodies) const {
  bool any = false;
  for (std::size_t i = 0; i < bodies.size(); ++i) {
    if (bodies[i].isStatic) continue;
    if (i >= rocks_.size() || !rocks_[i].released) {
      if (std::isfinite(bodies[i].releaseTime)) return false;  // still to come
      continue;
    }
    any = true;
    if (rocks_[i].state == RockState::kMoving) return false;
  }
  return any;
}

}  // namespace vf

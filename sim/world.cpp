// World::step() reads as the table of contents of one step (design.md):
//   step size (eq. 20)        solve/time_step.cpp
//   gravity                   solve/integrate.cpp
//   broad phase               collide/broad_phase.cpp
//   narrow phase (fig. 3)     collide/narrow_phase.cpp
//   impulses (eq. 15)         solve/impulse.cpp
//   explicit Euler, renormalise q   solve/integrate.cpp
#include "sim/world.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "sim/collide/broad_phase.h"
#include "sim/collide/narrow_phase.h"
#include "sim/collide/penetration.h"
#include "sim/core/error.h"
#include "sim/core/hash.h"
#include "sim/solve/impulse.h"
#include "sim/solve/integrate.h"
#include "sim/solve/time_step.h"

namespace vf {

namespace {

// Times closer than this are the same instant: release times are computed as start + i * interval
// and frame times as k / fps, which can differ in the last bit where they are meant to agree.
constexpr double kTimeTolerance = 1e-9;  // s

using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point& t) {
  const Clock::time_point now = Clock::now();
  const double s = std::chrono::duration<double>(now - t).count();
  t = now;
  return s;
}

}  // namespace

void RunStats::add(const StepStats& s) {
  dtMin = steps == 0 ? s.dt : std::min(dtMin, s.dt);
  dtMax = steps == 0 ? s.dt : std::max(dtMax, s.dt);
  ++steps;
  pairs += s.pairs;
  sphereTests += s.sphereTests;
  contacts += s.contacts;
  nonFinite += s.nonFinite;
  floored += s.floored;
  overlappingReleases += s.overlappingReleases;
  secondsPairs += s.secondsPairs;
  secondsContacts += s.secondsContacts;
  secondsSolve += s.secondsSolve;
  secondsIntegrate += s.secondsIntegrate;
}

World::World(WorldDef def) : def_(std::move(def)) {}

int World::addBody(const BodyDef& d) {
  VF_ASSERT(d.shape && d.shape->tree && d.shape->mass > 0);
  BodyInfo b;
  b.shape = d.shape;
  b.isStatic = d.isStatic;
  b.releaseTime = d.releaseTime;
  b.dropHeight = d.dropHeight;
  b.active = d.releaseTime <= time_ + kTimeTolerance;
  BodyState y;
  y.x = d.position;
  y.q = d.orientation.normalized();
  if (!d.isStatic) {
    b.invMass = 1.0 / d.shape->mass;
    b.inertiaBodyInv = d.shape->inertiaBodyInv;
    const Mat3 R = y.q.toRotationMatrix();
    y.P = d.shape->mass * d.velocity;
    y.L = R * d.shape->inertiaBody * R.transpose() * d.angularVelocity;  // L = I(t) w
  }
  const bool placeNow = b.active && b.dropHeight >= 0;
  bodies_.push_back(std::move(b));
  states_.push_back(y);
  if (placeNow) placeAbove(bodyCount() - 1, d.dropHeight);
  return bodyCount() - 1;
}

const StepStats& World::step(double maxDt) {
  VF_ASSERT(maxDt > 0);
  stepToward(time_ + maxDt);
  return last_;
}

void World::advanceTo(double t) {
  VF_ASSERT(t >= time_);
  while (time_ < t) {
    // A release time within kTimeTolerance of t is taken at t: no sliver steps.
    const double release = nextReleaseAfter(time_);
    stepToward(release < t - kTimeTolerance ? release : t);
    if (runaway_) throw RunawayError(*runaway_);
  }
}

double World::stableStep() const {
  return vf::stableStep(bodies_, states_, def_.gravity, def_.maxStep);
}

void World::stepToward(double target) {
  if (runaway_) return;
  StepStats s;
  Clock::time_point clock = Clock::now();

  // Step size: eq. 20 (or the fixed step), split so that `target` is reached in equal steps
  // none longer than the rule. The 1e-9 keeps a fixed step that divides the interval up to
  // rounding from producing one extra tiny step.
  const double remaining = target - time_;
  double rule = def_.fixedStep > 0 ? def_.fixedStep : stableStep();
  if (def_.fixedStep <= 0 && rule < def_.minStep) {  // a runaway body, not the user's choice
    rule = def_.minStep;
    s.floored = 1;
  }
  const double n = std::max(1.0, std::ceil(remaining / rule - 1e-9));
  const bool lands = n == 1.0;
  s.dt = lands ? remaining : remaining / n;

  applyGravity(bodies_, states_, def_.gravity, s.dt);

  pairs_.clear();
  findPairs(bodies_, states_, pairs_);
  s.pairs = pairs_.size();
  s.secondsPairs = secondsSince(clock);

  contacts_.clear();
  s.sphereTests =
      findContacts(bodies_, states_, pairs_, def_.groundHeight, def_.terrain.get(), contacts_);
  s.contacts = contacts_.size();
  s.secondsContacts = secondsSince(clock);

  SolverSettings solver;
  solver.material = def_.contact;
  solver.iterations = def_.solverIterations;
  solver.restingSpeed = 2 * def_.gravity.norm() * s.dt;  // what gravity adds in two steps
  solver.dt = s.dt;
  solveContacts(contacts_, bodies_, states_, solver, contactCache_);
  s.secondsSolve = secondsSince(clock);

  // Runaway check (run_guard.cpp) on the momenta of this step, before anything moves.
  runaway_ = guard_.check(bodies_, states_, def_.gravity, time_, s.dt, def_.limits);
  if (runaway_) return;

  s.nonFinite = integrate(bodies_, states_, s.dt);
  time_ = lands ? target : time_ + s.dt;
  s.overlappingReleases = releaseBodies();
  s.secondsIntegrate = secondsSince(clock);

  last_ = s;
  totals_.add(s);
}

Eigen::AlignedBox3d World::worldBounds(int id) const {
  Eigen::AlignedBox3d box;
  const Mat3 R = states_[id].q.toRotationMatrix();
  for (const Vec3& v : bodies_[id].shape->mesh.vertices) box.extend(states_[id].x + R * v);
  return box;
}

void World::placeAbove(int id, double clearance) {
  const auto footprint = [](const Eigen::AlignedBox3d& b) {
    return Eigen::AlignedBox2d(b.min().head<2>(), b.max().head<2>());
  };
  const Eigen::AlignedBox3d box = worldBounds(id);
  double top = -INFINITY;
  if (def_.groundHeight) top = *def_.groundHeight;
  if (def_.terrain) {
    const Vec3 c = box.center();
    top = std::max(top, def_.terrain->maxHeightNear(c.x(), c.y(),
                                                    0.5 * box.sizes().head<2>().maxCoeff()));
  }
  // What lies below is the pile: bodies that touched something in the last step (before the
  // first step, every placed body). A body still falling from an earlier release touches
  // nothing and does not lift this one, unless this one would be born inside it.
  std::vector<char> touching(bodyCount(), totals_.steps == 0 ? 1 : 0);
  for (const Contact& c : contacts_) {
    touching[c.a] = 1;
    if (c.b != kGround) touching[c.b] = 1;
  }
  std::vector<Eigen::AlignedBox3d> others(bodyCount());
  for (int j = 0; j < bodyCount(); ++j) {
    if (j == id || !bodies_[j].active) continue;
    others[j] = worldBounds(j);
    if (touching[j] && footprint(others[j]).intersects(footprint(box)))
      top = std::max(top, others[j].max().z());
  }
  if (!std::isfinite(top)) return;
  // Raise above airborne bodies the new one would overlap, until it overlaps none (each pass
  // moves it above at least one more body, so this ends).
  for (bool moved = true; moved;) {
    moved = false;
    const double lift = top + clearance - box.min().z();
    const Eigen::AlignedBox3d placed(box.min() + Vec3(0, 0, lift), box.max() + Vec3(0, 0, lift));
    for (int j = 0; j < bodyCount(); ++j)
      if (j != id && bodies_[j].active && !touching[j] && others[j].intersects(placed) &&
          others[j].max().z() > top) {
        top = others[j].max().z();
        moved = true;
      }
  }
  states_[id].x.z() += top + clearance - box.min().z();
}

std::uint64_t World::releaseBodies() {
  std::uint64_t overlapping = 0;
  for (int i = 0; i < bodyCount(); ++i) {
    BodyInfo& b = bodies_[i];
    if (b.active || b.releaseTime > time_ + kTimeTolerance) continue;
    if (b.dropHeight >= 0) placeAbove(i, b.dropHeight);
    const Collider mine = sphereTreeCollider(i, *b.shape->tree, states_[i].x, states_[i].q);
    std::vector<Contact> found;
    for (int j = 0; j < bodyCount() && found.empty(); ++j)
      if (bodies_[j].active)
        collide(mine, sphereTreeCollider(j, *bodies_[j].shape->tree, states_[j].x, states_[j].q),
                found);
    overlapping += found.empty() ? 0 : 1;
    b.active = true;
  }
  return overlapping;
}

double World::nextReleaseAfter(double t) const {
  double next = INFINITY;
  for (const BodyInfo& b : bodies_)
    if (!b.active && b.releaseTime > t + kTimeTolerance) next = std::min(next, b.releaseTime);
  return next;
}

Vec3 World::velocity(int id) const { return states_[id].P * bodies_[id].invMass; }

Vec3 World::angularVelocity(int id) const {
  const Mat3 R = states_[id].q.toRotationMatrix();
  return R * bodies_[id].inertiaBodyInv * R.transpose() * states_[id].L;
}

std::uint64_t World::stateHash() const {
  Hasher h;
  h.add(time_);
  for (int i = 0; i < bodyCount(); ++i) {
    const BodyState& y = states_[i];
    h.add(static_cast<std::uint64_t>(bodies_[i].active));
    for (double v : {y.x.x(), y.x.y(), y.x.z(), y.q.w(), y.q.x(), y.q.y(), y.q.z(), y.P.x(),
                     y.P.y(), y.P.z(), y.L.x(), y.L.y(), y.L.z()})
      h.add(v);
  }
  return h.value();
}

Diagnostics World::measure() const {
  Diagnostics d;
  const int n = bodyCount();
  std::vector<char> tunnelled(n, 0);
  for (int i = 0; i < n; ++i) {
    const BodyInfo& b = bodies_[i];
    if (!b.moves()) continue;
    const BodyState& y = states_[i];
    const double mass = b.shape->mass;
    d.kineticEnergy += 0.5 * y.P.dot(velocity(i)) + 0.5 * y.L.dot(angularVelocity(i));
    d.potentialEnergy -= mass * def_.gravity.dot(y.x);
    if (def_.groundHeight) {
      d.maxPenetrationBodyGround = std::max(
          d.maxPenetrationBodyGround, groundPenetration(*b.shape, {y.x, y.q}, *def_.groundHeight));
      if (y.x.z() < *def_.groundHeight) tunnelled[i] = 1;
    }
    if (def_.terrain) {
      d.maxPenetrationBodyGround = std::max(
          d.maxPenetrationBodyGround, terrainPenetration(*b.shape, {y.x, y.q}, *def_.terrain));
      if (y.x.z() < def_.terrain->heightAt(y.x.x(), y.x.y())) tunnelled[i] = 1;
    }
  }
  for (int a = 0; a < n; ++a) {
    if (!bodies_[a].active) continue;
    for (int b = a + 1; b < n; ++b) {
      if (!bodies_[b].active || (bodies_[a].isStatic && bodies_[b].isStatic)) continue;
      const Shape& sa = *bodies_[a].shape;
      const Shape& sb = *bodies_[b].shape;
      const double reach = 0.5 * (sa.diameter + sb.diameter);
      if ((states_[a].x - states_[b].x).squaredNorm() >= reach * reach) continue;
      const Pose pa{states_[a].x, states_[a].q}, pb{states_[b].x, states_[b].q};
      d.maxPenetrationBodyBody = std::max(
          {d.maxPenetrationBodyBody, meshPenetration(sa, pa, sb, pb), meshPenetration(sb, pb, sa, pa)});
      // A centre of mass outside its own solid (a hollow body) says nothing about tunnelling.
      if (bodies_[a].moves() && sa.centerInside && pointInsideBody(sb, pb, pa.x)) tunnelled[a] = 1;
      if (bodies_[b].moves() && sb.centerInside && pointInsideBody(sa, pa, pb.x)) tunnelled[b] = 1;
    }
  }
  d.tunnelled = static_cast<int>(std::count(tunnelled.begin(), tunnelled.end(), 1));
  return d;
}

}  // namespace vf

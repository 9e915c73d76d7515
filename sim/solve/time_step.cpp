// Eq. 17 asks that a sphere move less than its radius r in one step: dt * v_max <= r, with
// v_max = v_g,max + (l/2) w_max (eq. 18) and r = l / 2^(Lv+1) (eq. 19), giving eq. 20.
//
// The paper has one kind of body per scene; voxfall's scenes mix shapes and levels. We take
// r as the smallest leaf radius term l_i / 2^(Lv_i+1) over dynamic bodies (asleep ones too: a
// contact can wake one within the step), and v_max as the largest translational speed plus the
// largest rim speed (l_i/2) w_i over moving bodies: for a scene of identical bodies this is
// eq. 20 exactly, otherwise it is more conservative.
//
// One refinement: voxfall applies gravity before moving the bodies (the README's step order),
// so the speed that moves a body during the step is |v| + |g| dt, not |v|. Solving
// dt (v_max + |g| dt) = r for dt keeps eq. 17 true over the whole step; with g = 0 it is
// eq. 20 unchanged, and for the paper's scenes it differs from eq. 20 by under 5 %.
#include "sim/solve/time_step.h"

#include <algorithm>
#include <cmath>

#include "sim/collide/broad_phase.h"
#include "sim/collide/contact.h"
#include "sim/shape/heightfield.h"
#include "sim/shape/shape.h"

namespace vf {

double chooseStep(double remaining, double fixedStep, double stable, double minStep, bool& lands,
                  bool& floored) {
  double rule = fixedStep > 0 ? fixedStep : stable;
  floored = fixedStep <= 0 && rule < minStep;  // a runaway body, not the user's choice
  if (floored) rule = minStep;
  lands = false;
  if (!std::isfinite(remaining)) return rule;  // no end in sight: the rule's own step
  // The 1e-9 keeps a fixed step that divides the interval up to rounding from producing one
  // extra tiny step.
  const double n = std::max(1.0, std::ceil(remaining / rule - 1e-9));
  lands = n == 1.0;
  return lands ? remaining : remaining / n;
}

namespace {

// The step in which a point starting at `speed` under gravity g moves `distance`: the positive
// root of g dt^2 + speed dt - distance = 0 (written to avoid cancellation), or distance / speed
// for g = 0; maxStep when that is not a positive number (nothing moves, or non-finite speeds,
// whose bodies the integrator freezes). Not capped at maxStep.
double stepToMove(double distance, double speed, double g, double maxStep) {
  const double dt = g > 0 ? 2 * distance / (speed + std::sqrt(speed * speed + 4 * g * distance))
                          : (speed > 0 ? distance / speed : maxStep);
  return dt > 0 ? dt : maxStep;
}

}  // namespace

double stableStep(const std::vector<BodyInfo>& bodies, const std::vector<BodyState>& states,
                  const Vec3& gravity, double maxStep) {
  double radius = INFINITY;  // eq. 19, smallest over dynamic bodies
  double speed = 0;          // largest |v_g|
  double rimSpeed = 0;       // largest (l/2) |w|
  for (std::size_t i = 0; i < bodies.size(); ++i) {
    const BodyInfo& b = bodies[i];
    if (!b.dynamic()) continue;
    const Shape& s = *b.shape;
    // Asleep bodies count for r: one that a contact wakes in this step (solve/sleep.h) moves in
    // it, from rest, and its leaves too must move less than their radius. They add no speed.
    radius = std::min(radius, s.stepRadius());
    if (!b.moves()) continue;
    const BodyState& y = states[i];
    speed = std::max(speed, velocityOf(b, y).norm());
    rimSpeed = std::max(rimSpeed, 0.5 * s.diameter * angularVelocityOf(b, y).norm());
  }
  if (!std::isfinite(radius)) return maxStep;  // no dynamic body
  return std::min(stepToMove(radius, speed + rimSpeed, gravity.norm(), maxStep), maxStep);
}

// The clearance rule (an extension; the paper's rule is stableStep above). Eq. 17 makes every
// leaf sphere move less than its radius r in a step, so that a contact is found before it is
// deeper than r (two bodies: r_a + r_b) and nothing passes through anything. A body in flight,
// far from everything, need not obey it: while the fastest rock of a thousand falls off the
// cliff, eq. 20 makes every rock take its short steps. Here each moving body i gets
//   budget D_i: how far its fastest point moves in a step of maxStep (speed s_i = |v| + (l/2)|w|
//     as in eq. 18 but per body, plus gravity's |g| maxStep);
//   clearance c_i <= D_i, bounded by its bounding sphere's (radius R_i about the centre of mass,
//     enclosing every leaf sphere whatever the rotation) distance to the floor plane, to the
//     terrain (the sphere of radius R_i + c_i about x_i lies above Heightfield::surfaceBoundNear
//     over the square of half-side R_i + D_i, so no leaf inside it touches the surface or the
//     border wall: the containment argument of the terrain descent), and, for another body j
//     whose bounding sphere lies within reach, its share of their gap g_ij: c_i <= g_ij D_i /
//     (D_i + D_j), so c_i + c_j <= g_ij; bodies that do not move (asleep, static) have D = 0
//     and leave the whole gap to the other. For bodies farther apart along x than
//     R_i + D_i + R_j + D_j, g_ij > D_i + D_j >= c_i + c_j anyway (the sweep below skips them);
// and moves at most max(r_i, c_i) in the step. If two bodies i and j start g_ij apart, they end
// at most max(r_i, c_i) + max(r_j, c_j) - g_ij <= r_i + r_j deep in each other (c_i + c_j <=
// g_ij), and a body against the floor or the terrain at most r_i: the bounds eq. 17 gives.
// A body whose bounding sphere touches something (gap <= 0) gets c_i = 0: eq. 17, per body,
// which is never shorter than the paper's eq. 20 (maxima over bodies). The same state gives
// the same step (sorted with ties broken by id), whatever the thread count.
double clearanceStep(const std::vector<BodyInfo>& bodies, const std::vector<BodyState>& states,
                     const Vec3& gravity, double maxStep, const std::optional<double>& groundHeight,
                     const Heightfield* terrain) {
  const double g = gravity.norm();
  struct Reach {
    double lo, hi;  // x interval of the bounding sphere grown by the budget
    double speed = 0, radius = 0, reach = 0, budget = 0, clearance = 0;
    int id = 0;
  };
  std::vector<Reach> xs;
  xs.reserve(bodies.size());
  for (int i = 0; i < static_cast<int>(bodies.size()); ++i) {
    const BodyInfo& b = bodies[i];
    if (!b.active) continue;
    const Shape& s = *b.shape;
    const BodyState& y = states[i];
    Reach r;
    r.id = i;
    const double R = s.tree->boundingRadius;
    r.reach = R + roundingSlack(y.x, R);
    if (b.moves()) {
      r.speed = velocityOf(b, y).norm() + 0.5 * s.diameter * angularVelocityOf(b, y).norm();
      r.radius = s.stepRadius();
      r.budget = (r.speed + g * maxStep) * maxStep;
      if (!std::isfinite(r.budget)) r.budget = 0;  // the integrator freezes such bodies
      r.clearance = r.budget;
      if (groundHeight) r.clearance = std::min(r.clearance, y.x.z() - r.reach - *groundHeight);
      r.clearance = std::max(r.clearance, 0.0);
    } else if (b.dynamic()) {
      r.radius = s.stepRadius();  // asleep: may wake within the step (see stableStep)
    }
    r.lo = y.x.x() - r.reach - r.budget;
    r.hi = y.x.x() + r.reach + r.budget;
    xs.push_back(r);
  }
  sweepAlongX(xs, [&](Reach& a, Reach& b) {
    const double total = a.budget + b.budget;
    if (total == 0) return;  // neither moves
    // Skipped where the pair changes no step: both already move by their radii (a body moves
    // max(r, c), and c only shrinks), or they are at least D_a + D_b apart (shares >= budgets).
    if (a.clearance <= a.radius && b.clearance <= b.radius) return;
    const double far = a.reach + b.reach + total;
    const double d2 = (states[a.id].x - states[b.id].x).squaredNorm();
    if (d2 >= far * far) return;
    const double gap = std::sqrt(d2) - a.reach - b.reach;
    if (gap <= 0) {
      a.clearance = b.clearance = 0;
      return;
    }
    a.clearance = std::min(a.clearance, gap * (a.budget / total));
    b.clearance = std::min(b.clearance, gap * (b.budget / total));
  });
  // The terrain last, and only where it can matter: a body moves max(r, c), so once c <= r
  // nothing lowers its step; and the surface under the centre is below the bound over any
  // square about it, so a centre less than R + r above it settles c <= r without the bound.
  if (terrain)
    for (Reach& r : xs) {
      if (r.clearance <= r.radius) continue;
      const Vec3& x = states[r.id].x;
      if (x.z() - r.reach - terrain->heightAt(x.x(), x.y()) < r.radius) {  // NaN: no data
        r.clearance = 0;
        continue;
      }
      // Above every sample (the bound is capped by the samples, plus its 1e-9 m): no change.
      if (x.z() - r.reach - r.clearance > terrain->zMax + 1e-9) continue;
      const double top = terrain->surfaceBoundNear(x.x(), x.y(), r.reach + r.budget);
      r.clearance = std::max(std::min(r.clearance, x.z() - r.reach - top), 0.0);  // -inf: none
    }
  double dt = maxStep;
  for (const Reach& r : xs) {
    if (bodies[r.id].sleeping) {  // woken within the step, it moves from rest (see stableStep)
      dt = std::min(dt, stepToMove(r.radius, 0.0, g, maxStep));
      continue;
    }
    if (r.budget == 0) continue;
    dt = std::min(dt, stepToMove(std::max(r.radius, r.clearance), r.speed, g, maxStep));
  }
  return dt;
}

}  // namespace vf

// Release placement (release.h). Kept out of world.cpp so that World::step stays the table
// of contents of a step.
#include "sim/solve/release.h"

#include <algorithm>
#include <cmath>

#include "sim/collide/narrow_phase.h"
#include "sim/shape/heightfield.h"
#include "sim/shape/shape.h"

namespace vf {

namespace {

// The body's mesh vertices in its current pose.
std::vector<Vec3> worldVertices(const BodyInfo& b, const BodyState& y) {
  const Mat3 R = y.q.toRotationMatrix();
  std::vector<Vec3> pts;
  pts.reserve(b.shape->mesh.vertices.size());
  for (const Vec3& v : b.shape->mesh.vertices) pts.push_back(y.x + R * v);
  return pts;
}

// Bounds of the body's mesh in its current pose (no allocation: every active body's bounds are
// taken at every release).
Eigen::AlignedBox3d meshBounds(const BodyInfo& b, const BodyState& y) {
  Eigen::AlignedBox3d box;
  const Mat3 R = y.q.toRotationMatrix();
  for (const Vec3& v : b.shape->mesh.vertices) box.extend(y.x + R * v);
  return box;
}

Eigen::AlignedBox2d footprint(const Eigen::AlignedBox3d& b) {
  return Eigen::AlignedBox2d(b.min().head<2>(), b.max().head<2>());
}

}  // namespace

double releaseLift(int id, double clearance, const std::vector<BodyInfo>& bodies,
                   const std::vector<BodyState>& states, const std::vector<Contact>& lastContacts,
                   bool firstStep, const ReleaseGround& ground) {
  const int n = static_cast<int>(bodies.size());
  const BodyInfo& me = bodies[id];
  const std::vector<Vec3> pts = worldVertices(me, states[id]);
  Eigen::AlignedBox3d box;
  for (const Vec3& p : pts) box.extend(p);
  double top = -INFINITY;
  if (ground.floorHeight) top = *ground.floorHeight;
  if (ground.terrain)  // the surface directly under the body, not the highest grid node near it
    top = std::max(top, ground.terrain->surfaceUnder(pts, box.min().z()));
  // What lies below is the pile: bodies that touched something in the last step (before the
  // first step, every placed body). A body still falling from an earlier release touches
  // nothing and does not lift this one, unless this one would be born inside it.
  // A sleeping body rests on something, so it counts as touching.
  std::vector<char> touching(n, firstStep ? 1 : 0);
  for (int j = 0; j < n; ++j)
    if (bodies[j].sleeping) touching[j] = 1;
  for (const Contact& c : lastContacts) {
    touching[c.a] = 1;
    if (c.b != kGround) touching[c.b] = 1;
  }
  const double ownPad = me.shape->tree->leaves().radius;
  std::vector<Eigen::AlignedBox3d> others(n);
  for (int j = 0; j < n; ++j) {
    if (j == id || !bodies[j].active) continue;
    others[j] = meshBounds(bodies[j], states[j]);
    const Vec3 pad = Vec3::Constant(ownPad + bodies[j].shape->tree->leaves().radius);
    others[j] = Eigen::AlignedBox3d(others[j].min() - pad, others[j].max() + pad);
    if (touching[j] && footprint(others[j]).intersects(footprint(box)))
      top = std::max(top, others[j].max().z() - pad.z());
  }
  if (!std::isfinite(top)) return 0;
  // Raise above airborne bodies the new one would overlap, until it overlaps none (each pass
  // moves it above at least one more body, so this ends).
  for (bool moved = true; moved;) {
    moved = false;
    const double lift = top + clearance - box.min().z();
    const Eigen::AlignedBox3d placed(box.min() + Vec3(0, 0, lift), box.max() + Vec3(0, 0, lift));
    for (int j = 0; j < n; ++j)
      if (j != id && bodies[j].active && !touching[j] && others[j].intersects(placed) &&
          others[j].max().z() > top) {
        top = others[j].max().z();
        moved = true;
      }
  }
  return top + clearance - box.min().z();
}

double releaseClearLift(int id, const std::vector<BodyInfo>& bodies,
                        const std::vector<BodyState>& states) {
  const int n = static_cast<int>(bodies.size());
  const Eigen::AlignedBox3d box = meshBounds(bodies[id], states[id]);
  const double ownPad = bodies[id].shape->tree->leaves().radius;
  std::vector<Eigen::AlignedBox3d> others;
  for (int j = 0; j < n; ++j) {
    if (j == id || !bodies[j].active) continue;
    const Eigen::AlignedBox3d b = meshBounds(bodies[j], states[j]);
    const Vec3 pad = Vec3::Constant(ownPad + bodies[j].shape->tree->leaves().radius);
    others.emplace_back(b.min() - pad, b.max() + pad);
  }
  // Each pass raises the body onto the top of one more box it meets, so this ends; a lift
  // only grows, so rounding cannot make it cycle.
  double lift = 0;
  for (bool moved = true; moved;) {
    moved = false;
    const Eigen::AlignedBox3d placed(box.min() + Vec3(0, 0, lift), box.max() + Vec3(0, 0, lift));
    for (const Eigen::AlignedBox3d& o : others)
      if (o.intersects(placed) && o.max().z() - box.min().z() > lift) {
        lift = o.max().z() - box.min().z();
        moved = true;
      }
  }
  return lift;
}

bool overlapsActiveBody(int id, const std::vector<BodyInfo>& bodies,
                        const std::vector<BodyState>& states) {
  const Collider mine = sphereTreeCollider(id, *bodies[id].shape->tree, states[id].x, states[id].q);
  std::vector<Contact> found;
  for (int j = 0; j < static_cast<int>(bodies.size()) && found.empty(); ++j)
    if (j != id && bodies[j].active)  // World asks before it activates `id`
      collide(mine, sphereTreeCollider(j, *bodies[j].shape->tree, states[j].x, states[j].q), found);
  return !found.empty();
}

}  // namespace vf

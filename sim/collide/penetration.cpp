#include "sim/collide/penetration.h"

#include <algorithm>

#include "sim/collide/broad_phase.h"

namespace vf {

namespace {
// World point -> B's body frame.
Vec3 toBody(const Pose& p, const Vec3& world) { return p.q.conjugate() * (world - p.x); }
}  // namespace

double meshPenetration(const Shape& a, const Pose& pa, const Shape& b, const Pose& pb,
                       double atLeast) {
  const Eigen::AlignedBox3d boxB = b.sides->bounds();
  // A -> B body frames in one rotation and one offset.
  const Mat3 R = (pb.q.conjugate() * pa.q).toRotationMatrix();
  const Vec3 t = pb.q.conjugate() * (pa.x - pb.x);
  const double tMax = t.lpNorm<Eigen::Infinity>();
  double deepest = std::max(atLeast, 0.0);
  const SampleClusters& samples = a.surfaceSamples;
  for (const SampleClusters::Cluster& cluster : samples.clusters) {
    // A cluster whose sphere misses B's bounds holds no sample inside them. The slack covers
    // the rounding by which a sample moved on its own may land nearer the box than its sphere.
    const Vec3 centre = t + R * cluster.centre;
    const double reach =
        cluster.radius + 1e-9 * (1 + tMax + cluster.centre.norm() + cluster.radius);
    if (boxB.squaredExteriorDistance(centre) > reach * reach) continue;
    for (std::uint32_t i = cluster.begin; i < cluster.end; ++i) {
      const Vec3 inB = t + R * samples.points[i];
      if (!boxB.contains(inB)) continue;  // outside B's bounds: outside B
      // In a grid cell wholly outside B (B's cavity, say): outside B, as the search would find.
      if (b.sides->side(inB) == SideGrid::Side::kOutside) continue;
      // Inside B, the way out to the nearest face of B's bounds crosses B's surface: a sample
      // no farther than `deepest` from those faces cannot be deeper.
      const double toFace = std::min((inB - boxB.min()).minCoeff(), (boxB.max() - inB).minCoeff());
      if (toFace <= deepest) continue;
      // Nor can a sample within `deepest` of B's surface: the search may stop there, and what
      // it returns beyond that distance is the exact nearest point.
      const MeshBvh::Nearest n = b.bvh->nearest(inB, deepest);
      if (n.distance > deepest && n.inside) deepest = n.distance;
    }
  }
  return deepest;
}

double groundPenetration(const Shape& s, const Pose& p, double height) {
  const Mat3 R = p.q.toRotationMatrix();
  double deepest = 0;
  for (const Vec3& v : s.mesh.vertices) deepest = std::max(deepest, height - (p.x + R * v).z());
  return deepest;
}

double terrainPenetration(const Shape& s, const Pose& p, const Heightfield& terrain) {
  const Mat3 R = p.q.toRotationMatrix();
  double deepest = 0;
  for (const Vec3& v : s.mesh.vertices) {
    const Vec3 w = p.x + R * v;
    const double h = terrain.heightAt(w.x(), w.y());
    if (h > w.z()) deepest = std::max(deepest, h - w.z());  // false for NaN
  }
  return deepest;
}

bool pointInsideBody(const Shape& s, const Pose& p, const Vec3& point) {
  const Vec3 local = toBody(p, point);
  const SideGrid::Side side = s.sides->side(local);  // outside the bounds: kOutside
  if (side != SideGrid::Side::kNearSurface) return side == SideGrid::Side::kInside;
  return s.bvh->nearest(local).inside;
}

Diagnostics measureDiagnostics(const std::vector<BodyInfo>& bodies,
                               const std::vector<BodyState>& states, const Vec3& gravity,
                               const std::optional<double>& groundHeight,
                               const Heightfield* terrain) {
  Diagnostics d;
  const int n = static_cast<int>(bodies.size());
  std::vector<char> tunnelled(n, 0);
  for (int i = 0; i < n; ++i) {
    const BodyInfo& b = bodies[i];
    if (!b.dynamic()) continue;
    const BodyState& y = states[i];
    d.kineticEnergy += 0.5 * y.P.dot(velocityOf(b, y)) + 0.5 * y.L.dot(angularVelocityOf(b, y));
    d.potentialEnergy -= b.shape->mass * gravity.dot(y.x);
    if (groundHeight) {
      d.maxPenetrationBodyGround = std::max(d.maxPenetrationBodyGround,
                                            groundPenetration(*b.shape, {y.x, y.q}, *groundHeight));
      if (y.x.z() < *groundHeight) tunnelled[i] = 1;
    }
    if (terrain) {
      d.maxPenetrationBodyGround =
          std::max(d.maxPenetrationBodyGround, terrainPenetration(*b.shape, {y.x, y.q}, *terrain));
      if (y.x.z() < terrain->heightAt(y.x.x(), y.x.y())) tunnelled[i] = 1;
    }
  }
  // The broad phase's bounding spheres enclose every leaf sphere and so the mesh: a superset of
  // the pairs whose meshes may overlap (sleeping bodies included: diagnostics see every body).
  std::vector<BodyPair> pairs;
  findPairs(bodies, states, pairs);
  for (const BodyPair& p : pairs) {
    const int a = p.a, b = p.b;
    const Shape& sa = *bodies[a].shape;
    const Shape& sb = *bodies[b].shape;
    const double reach = 0.5 * (sa.diameter + sb.diameter);
    if ((states[a].x - states[b].x).squaredNorm() >= reach * reach) continue;
    const Pose pa{states[a].x, states[a].q}, pb{states[b].x, states[b].q};
    d.maxPenetrationBodyBody = meshPenetration(sa, pa, sb, pb, d.maxPenetrationBodyBody);
    d.maxPenetrationBodyBody = meshPenetration(sb, pb, sa, pa, d.maxPenetrationBodyBody);
    // A centre of mass outside its own solid (a hollow body) says nothing about tunnelling.
    if (bodies[a].dynamic() && sa.centerInside && pointInsideBody(sb, pb, pa.x)) tunnelled[a] = 1;
    if (bodies[b].dynamic() && sb.centerInside && pointInsideBody(sa, pa, pb.x)) tunnelled[b] = 1;
  }
  d.tunnelled = static_cast<int>(std::count(tunnelled.begin(), tunnelled.end(), 1));
  return d;
}

}  // namespace vf

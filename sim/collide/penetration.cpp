#include "sim/collide/penetration.h"

#include <algorithm>

#include "sim/geometry/mesh_query.h"

namespace vf {

namespace {
// World point -> B's body frame.
Vec3 toBody(const Pose& p, const Vec3& world) { return p.q.conjugate() * (world - p.x); }
}  // namespace

double meshPenetration(const Shape& a, const Pose& pa, const Shape& b, const Pose& pb) {
  const Eigen::AlignedBox3d boxB = b.mesh.bounds();
  double deepest = 0;
  for (const Vec3& s : surfaceSamples(a.mesh)) {
    const Vec3 inB = toBody(pb, pa.x + pa.q * s);
    if (!boxB.contains(inB) || !pointInsideMesh(b.mesh, inB)) continue;
    deepest = std::max(deepest, distanceToMesh(b.mesh, inB));
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
  return s.mesh.bounds().contains(local) && pointInsideMesh(s.mesh, local);
}

}  // namespace vf

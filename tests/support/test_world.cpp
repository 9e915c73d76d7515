#include "tests/support/test_world.h"

#include <algorithm>
#include <utility>

namespace vf::test {

TriMesh boxMesh(double a, double b, double c) {
  TriMesh m;
  for (int i = 0; i < 8; ++i)
    m.vertices.push_back(
        Vec3((i & 1 ? 0.5 : -0.5) * a, (i & 2 ? 0.5 : -0.5) * b, (i & 4 ? 0.5 : -0.5) * c));
  // Two triangles per face, counter-clockwise seen from outside.
  m.triangles = {{0, 2, 3}, {0, 3, 1},   // -z
                 {4, 5, 7}, {4, 7, 6},   // +z
                 {0, 1, 5}, {0, 5, 4},   // -y
                 {2, 6, 7}, {2, 7, 3},   // +y
                 {0, 4, 6}, {0, 6, 2},   // -x
                 {1, 3, 7}, {1, 7, 5}};  // +x
  return m;
}

std::shared_ptr<const Shape> boxShape(double a, double b, double c, double density, int level) {
  return makeShape("box", boxMesh(a, b, c), Vec3::Ones(), density, level);
}

std::vector<BodyInfo> oneBody(std::shared_ptr<const Shape> s) {
  std::vector<BodyInfo> bodies(1);
  bodies[0].invMass = 1 / s->mass;
  bodies[0].shape = std::move(s);
  return bodies;
}

double restOffset(const Shape& s) {
  const SphereTreeLevel& leaves = s.tree->leaves();
  double lowest = 0;
  for (const Vec3& c : leaves.centers) lowest = std::min(lowest, c.z() - leaves.radius);
  return -lowest;
}

Rebound dropAndWatchRebound(World& world, double zTouch, double dt, double until) {
  Rebound r;
  while (world.time() < until) {
    const double v = world.velocity(0).z();
    world.step(dt);
    const double v2 = world.velocity(0).z();
    if (!r.bounced && v < 0 && v2 > 0) {
      r.bounced = true;
      r.vBefore = v;
      r.vAfter = v2;
    }
    if (r.bounced) r.apex = std::max(r.apex, world.state(0).x.z() - zTouch);
  }
  return r;
}

BodyDef bodyAt(std::shared_ptr<const Shape> s, const Vec3& x, double release) {
  BodyDef b;
  b.shape = std::move(s);
  b.position = x;
  b.releaseTime = release;
  return b;
}

Heightfield flatHeightfield(int nx, int ny, double cell, double z, double x0, double y0) {
  Heightfield h;
  h.nx = nx;
  h.ny = ny;
  h.cell = cell;
  h.x0 = x0;
  h.y0 = y0;
  h.z.assign(static_cast<std::size_t>(nx) * ny, z);
  h.zMin = h.zMax = z;
  return h;
}

std::string sourcePath(const std::string& relative) {
  return std::string(VOXFALL_SOURCE_DIR) + "/" + relative;
}

}  // namespace vf::test

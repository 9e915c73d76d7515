// Property test: 1,000 seeded random drops. Each drop throws one to three bodies of random
// shapes (the example meshes and spot.obj) at random scales, orientations, velocities up to
// 30 m/s and spins up to 20 rad/s onto the floor or a hilly terrain (with a floor below it) and
// onto each other, at level 2 for 1 s. Invariants, checked at every output frame (20 per
// second):
//   - every state is finite and the run guard never stops the run;
//   - no body ends below the ground (its centre of mass under the floor or the terrain);
//   - the total energy never rises above its start by more than 10 % of the energy available
//     (kinetic energy at the start plus m g (height above the lowest ground + l)): contacts only
//     dissipate, gravity conserves;
//   - no mesh is inside another, or below the ground, by more than one leaf-voxel edge (eq. 20
//     lets a leaf sphere move at most its radius per step).
// A failure prints the drop's seed; rerun one drop with VOXFALL_DROP_SEED=N. VOXFALL_DROP_COUNT=N
// runs only the first N drops: the sanitizer tree (CMakePresets.json) runs 250, since ASan and
// UBSan at -O1 make a drop about 40x slower (the thousand took 282 s there against 6.7 s in the
// Release tree), and what they look for, memory errors and undefined behaviour, the first 250
// exercise on the same code paths (every shape, the floor and the terrain, bodies meeting);
// the normal tree still runs all 1,000 for the invariants.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <memory>
#include <numbers>
#include <string>
#include <vector>

#include "sim/core/prng.h"
#include "sim/geometry/mesh_checks.h"
#include "sim/geometry/mesh_import.h"
#include "sim/run_guard.h"
#include "sim/shape/shape.h"
#include "sim/world.h"
#include "tests/support/test_world.h"

namespace vf {
namespace {

constexpr int kDrops = 1000;
constexpr int kLevel = 2;
constexpr double kDuration = 1.0;  // s
constexpr double kFps = 20;
constexpr double kFloor = -1.0;  // the floor below the terrain, m

const std::vector<TriMesh>& exampleMeshes() {
  static const std::vector<TriMesh> meshes = [] {
    std::vector<TriMesh> out;
    for (const char* file :
         {"scenes/meshes/cube.obj", "scenes/meshes/block.obj", "scenes/meshes/cross.obj",
          "scenes/meshes/rock.obj", "scenes/meshes/highpoly_block.obj",
          "scenes/meshes/stack_block.obj", "scenes/meshes/barrel.obj", "tests/data/spot.obj"}) {
      TriMesh m = importMesh(test::sourcePath(file));
      validateClosedMesh(m, file);
      // Normalise to a 1 m bounding-box diagonal so that the random scale is the size.
      const double d = m.bounds().diagonal().norm();
      m.scale(Vec3::Constant(1.0 / d));
      out.push_back(std::move(m));
    }
    return out;
  }();
  return meshes;
}

// Hills over [-8, 8]^2 (0.5 m cells): z = 0.4 sin(x) cos(0.7 y) + 0.15 x.
std::shared_ptr<const Heightfield> hills() {
  static const auto terrain = [] {
    auto h = std::make_shared<Heightfield>();
    h->nx = h->ny = 33;
    h->x0 = h->y0 = -8;
    h->cell = 0.5;
    h->z.resize(33 * 33);
    h->zMin = INFINITY;
    h->zMax = -INFINITY;
    for (int j = 0; j < 33; ++j)
      for (int i = 0; i < 33; ++i) {
        const double x = h->x0 + i * h->cell, y = h->y0 + j * h->cell;
        const double z = 0.4 * std::sin(x) * std::cos(0.7 * y) + 0.15 * x;
        h->z[j * 33 + i] = z;
        h->zMin = std::min(h->zMin, z);
        h->zMax = std::max(h->zMax, z);
      }
    return std::shared_ptr<const Heightfield>(h);
  }();
  return terrain;
}

Quat randomRotation(Prng& rng) {
  // Shoemake's uniform rotation from three uniforms.
  const double u1 = rng.uniform(), u2 = rng.uniform(), u3 = rng.uniform();
  const double a = std::sqrt(1 - u1), b = std::sqrt(u1), t = 2 * std::numbers::pi;
  return Quat(b * std::cos(t * u3), a * std::sin(t * u2), a * std::cos(t * u2),
              b * std::sin(t * u3));
}

Vec3 randomDirection(Prng& rng) {
  const double z = rng.uniform(-1, 1), phi = rng.uniform(0, 2 * std::numbers::pi);
  const double s = std::sqrt(1 - z * z);
  return Vec3(s * std::cos(phi), s * std::sin(phi), z);
}

struct DropResult {
  std::string failure;     // "" when every invariant held
  bool touched = false;    // some body met the ground or another body
  bool bodiesMet = false;  // two bodies' bounding spheres overlapped in some step
};

// One drop.
DropResult drop(std::uint64_t seed) {
  DropResult result;
  Prng rng(seed);
  WorldDef def;
  const bool onTerrain = rng.uniform() < 0.5;
  if (onTerrain) {
    def.terrain = hills();
    def.groundHeight = kFloor;
  } else {
    def.groundHeight = 0.0;
  }
  test::RockFallWorld rock(def, {});  // with the rock monitor, as a scene on terrain has
  World& world = rock.world;
  const auto groundAt = [&](double x, double y) {
    if (!onTerrain) return 0.0;
    const double h = def.terrain->heightAt(x, y);
    return std::isnan(h) ? kFloor : h;
  };

  const int bodies = 1 + static_cast<int>(rng.uniform() * 3);
  // The bodies share most of their motion (so that they meet: the upper ones land on the lower
  // ones) plus a little each of their own; speeds are capped at 30 m/s.
  const Vec3 common = rng.uniform(0, 28) * randomDirection(rng);
  const double x0 = rng.uniform(-2, 2), y0 = rng.uniform(-2, 2);
  double top = -INFINITY;  // bodies are stacked in the air so that none starts inside another
  double available = 0;
  double leafEdge = 0;
  const double g = def.gravity.norm();
  const double lowest = onTerrain ? kFloor : 0.0;
  for (int i = 0; i < bodies; ++i) {
    const auto& meshes = exampleMeshes();
    const auto which =
        std::min(meshes.size() - 1, static_cast<std::size_t>(rng.uniform() * meshes.size()));
    const double size = rng.uniform(0.15, 0.8);  // bounding-box diagonal, m
    // append, not "m" + ...: GCC 12 warns falsely (-Wrestrict) on that operator+ inlined here.
    const std::string name = std::string("m").append(std::to_string(which));
    auto shape = makeShape(name, meshes[which], Vec3::Constant(size), 800, kLevel);
    const double x = x0 + rng.uniform(-0.2, 0.2), y = y0 + rng.uniform(-0.2, 0.2);
    const double base = std::max(groundAt(x, y) + 0.1, top + 0.05);
    BodyDef b;
    b.shape = shape;
    b.position = Vec3(x, y, base + 0.5 * shape->diameter + rng.uniform(0, 0.5));
    b.orientation = randomRotation(rng);
    b.velocity = common + rng.uniform(0, 2) * randomDirection(rng);
    b.angularVelocity = rng.uniform(0, 20) * randomDirection(rng);
    top = b.position.z() + 0.5 * shape->diameter;
    world.addBody(b);
    const double m = shape->mass;
    available += 0.5 * m * b.velocity.squaredNorm() +
                 0.5 * b.angularVelocity.dot(b.orientation.toRotationMatrix() * shape->inertiaBody *
                                             b.orientation.toRotationMatrix().transpose() *
                                             b.angularVelocity) +
                 m * g * (b.position.z() - lowest + shape->diameter);
    leafEdge = std::max(leafEdge, shape->tree->leaves().edge);
  }

  const Diagnostics start = world.measure();
  const double e0 = start.kineticEnergy + start.potentialEnergy;
  const int frames = static_cast<int>(std::lround(kDuration * kFps));
  for (int k = 1; k <= frames; ++k) {
    const double t = k / kFps;
    try {
      world.advanceTo(t);
    } catch (const RunawayError& e) {
      result.failure = std::string("run guard stopped the run: ") + e.what();
      return result;
    }
    for (int i = 0; i < world.bodyCount(); ++i) {
      const BodyState& y = world.state(i);
      if (!y.x.allFinite() || !y.q.coeffs().allFinite() || !y.P.allFinite() || !y.L.allFinite())
        result.failure = "body " + std::to_string(i) + " not finite at t = " + std::to_string(t);
    }
    if (!result.failure.empty()) return result;
    result.touched = result.touched || world.totals().contacts > 0;
    result.bodiesMet = result.bodiesMet || world.totals().pairs > 0;
    const Diagnostics d = world.measure();
    const double e = d.kineticEnergy + d.potentialEnergy;
    std::string& f = result.failure;
    if (e - e0 > 0.1 * available)
      f = "energy rose by " + std::to_string(e - e0) + " J at t = " + std::to_string(t) +
          " (available " + std::to_string(available) + " J)";
    else if (d.maxPenetrationBodyBody > leafEdge)
      f = "bodies interpenetrate by " + std::to_string(d.maxPenetrationBodyBody) +
          " m at t = " + std::to_string(t) + " (leaf edge " + std::to_string(leafEdge) + ")";
    else if (d.maxPenetrationBodyGround > leafEdge)
      f = "a body is " + std::to_string(d.maxPenetrationBodyGround) +
          " m below the ground at t = " + std::to_string(t) + " (leaf edge " +
          std::to_string(leafEdge) + ")";
    else if (k == frames && d.tunnelled > 0)
      f = std::to_string(d.tunnelled) + " bodies end below the ground or inside another";
    if (!f.empty()) return result;
  }
  return result;
}

TEST(RandomDrops, ThousandSeededDropsKeepTheInvariants) {
  std::uint64_t first = 1, count = kDrops;
  if (const char* s = std::getenv("VOXFALL_DROP_COUNT")) {
    count = std::strtoull(s, nullptr, 10);
    ASSERT_GT(count, 0u) << "VOXFALL_DROP_COUNT must be a positive number of drops";
  }
  if (const char* s = std::getenv("VOXFALL_DROP_SEED")) {
    first = std::strtoull(s, nullptr, 10);
    count = 1;
  }
  int failures = 0, touched = 0, met = 0;
  for (std::uint64_t seed = first; seed < first + count && failures < 5; ++seed) {
    const DropResult r = drop(seed);
    touched += r.touched ? 1 : 0;
    met += r.bodiesMet ? 1 : 0;
    if (!r.failure.empty()) {
      ++failures;
      ADD_FAILURE() << "drop seed " << seed << " (rerun: VOXFALL_DROP_SEED=" << seed
                    << "): " << r.failure;
    }
  }
  // The drops must exercise what the invariants are about: contacts with the ground in most,
  // bodies meeting bodies in many.
  if (count >= 100) {
    EXPECT_GT(touched, static_cast<int>(count / 2));
    EXPECT_GT(met, static_cast<int>(count / 4));
  }
  std::printf("%d of %d drops touched something, %d had bodies meeting\n", touched,
              static_cast<int>(count), met);
}

}  // namespace
}  // namespace vf

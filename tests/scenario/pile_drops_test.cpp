// Property test: bodies dropped one by one onto piles that fall asleep between drops, with
// contact reduction and sleeping (the fast path), held to the bound eq. 20 gives the paper's
// method.
//
// The bound. Eq. 17 asks that no leaf sphere move more than its radius in a step; eq. 18's
// v_max counts the rim speed (l/2) w, so no point of body i moves more than
// r_i = l_i / 2^(Lv+1) (eq. 19) in one step (time_step.cpp keeps this with gravity's increment).
// Two bodies' points therefore close in on each other by at most r_a + r_b in a step. Meshes
// that touch have touching leaf spheres (a leaf sphere encloses its surface voxel), so the
// contact is found at the start of the next step and the solver lets it approach no further.
// Hence the paper's claim that nothing interpenetrates at the eq.-20 step, in numbers: no
// surface point of one mesh lies deeper in another than r_a + r_b, at the end of any step.
// The extensions must keep to it: a sleeping island is not stepped, and a reduced contact set
// stands for the leaf contacts it replaces; neither may let a pile sink further.
//
// The scenes: as example 4 (scenes/stack.toml), one body lies on the floor and 8 to 16 more are
// dropped alternately at two spots 0.4 m apart, with up to 5 cm of seeded scatter, each from
// 0.1 to 1 m above what lies under it (drop_height), 0.5 to 1.5 s apart, so that the pile often
// falls asleep between drops and each landing wakes it; one shape per scene, from example 4's
// and example 2's blocks, example 1's cube and example 6's rock, at the paper's Lv 4. The true
// meshes are measured after every step (meshPenetration, the diagnostics' checker).
// With the paper's method every scene stays within the bound (run by hand on the same 60
// seeds: at most 0.69 of it, in scene 15; it takes over ten times as long, so it is not run
// here). What keeps the fast path within it is the warm start across sleep and across
// re-chosen representatives (sim/solve/contact_cache.cpp): without both, scenes 3, 15, 19 and
// 40 sink past the bound, by up to a quarter (either alone keeps these 60 within it).
// A failure names the scene's seed; VOXFALL_PILE_SEED=N runs that scene alone.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <memory>
#include <string>
#include <vector>

#include "sim/collide/penetration.h"
#include "sim/core/prng.h"
#include "sim/geometry/mesh_import.h"
#include "sim/shape/shape.h"
#include "sim/world.h"
#include "tests/support/test_world.h"

namespace vf {
namespace {

constexpr int kScenes = 60;
constexpr int kLevel = 4;

struct PileShape {
  const char* mesh;
  double scale, density;  // as the paper's scenes have them
};
constexpr PileShape kShapes[] = {{"scenes/meshes/stack_block.obj", 1.0, 800},
                                 {"scenes/meshes/block.obj", 1.0, 800},
                                 {"scenes/meshes/cube.obj", 0.3, 800},
                                 {"scenes/meshes/rock.obj", 1.0, 2500}};

const std::vector<std::shared_ptr<const Shape>>& pileShapes() {
  static const auto shapes = [] {
    std::vector<std::shared_ptr<const Shape>> out;
    for (const PileShape& p : kShapes)
      out.push_back(makeShape(p.mesh, importMesh(test::sourcePath(p.mesh)), Vec3::Constant(p.scale),
                              p.density, kLevel));
    return out;
  }();
  return shapes;
}

struct PileRun {
  double worstShare = 0;  // deepest interpenetration of a pair over its r_a + r_b
  std::string worst;      // where that was
  int woken = 0;          // bodies woken from sleep
  std::uint64_t overlappingReleases = 0;
};

PileRun dropOntoPile(std::uint64_t seed) {
  Prng rng(seed);
  WorldDef def;
  def.groundHeight = 0.0;
  def.contactReduction = true;
  def.sleep = true;
  World world(def);
  const auto& shapes = pileShapes();
  const auto shape =
      shapes[std::min(shapes.size() - 1, static_cast<std::size_t>(rng.uniform() * shapes.size()))];
  const int drops = 8 + static_cast<int>(rng.uniform() * 9);
  const double interval = rng.uniform(0.5, 1.5), height = rng.uniform(0.1, 1.0);
  double last = 0;
  // Body 0 lies on the floor from the start, its leaf spheres touching it; body i > 0 is
  // dropped at 1.5 s + i * interval.
  for (int i = 0; i <= drops; ++i) {
    const Vec3 spot(i % 2 ? 0.2 : -0.2, 0, i == 0 ? test::restOffset(*shape) : 0.0);
    const Vec3 scatter(rng.uniform(-0.05, 0.05), rng.uniform(-0.05, 0.05), 0);
    BodyDef b = test::bodyAt(shape, spot + scatter, i == 0 ? 0.0 : 1.5 + i * interval);
    if (i > 0) b.dropHeight = height;
    last = b.releaseTime;
    world.addBody(b);
  }
  PileRun run;
  std::vector<char> asleep(world.bodyCount());
  while (world.time() < last + 2.0) {
    for (int i = 0; i < world.bodyCount(); ++i) asleep[i] = world.isSleeping(i);
    world.stepNext();
    for (int i = 0; i < world.bodyCount(); ++i) run.woken += asleep[i] && !world.isSleeping(i);
    for (int i = 0; i < world.bodyCount(); ++i)
      for (int j = i + 1; j < world.bodyCount(); ++j) {
        if (!world.isActive(i) || !world.isActive(j)) continue;
        const BodyState &a = world.state(i), &b = world.state(j);
        if ((a.x - b.x).norm() > shape->tree->boundingRadius * 2) continue;
        const double depth = std::max(meshPenetration(*shape, {a.x, a.q}, *shape, {b.x, b.q}),
                                      meshPenetration(*shape, {b.x, b.q}, *shape, {a.x, a.q}));
        const double share = depth / (2 * shape->stepRadius());
        if (share > run.worstShare) {
          run.worstShare = share;
          run.worst = "bodies " + std::to_string(i) + " and " + std::to_string(j) + " (" +
                      shape->name + ") " + std::to_string(depth * 1000) +
                      " mm deep at t = " + std::to_string(world.time()) + " s";
        }
      }
  }
  run.overlappingReleases = world.totals().overlappingReleases;
  return run;
}

TEST(PileDrops, FastPathKeepsEveryPairWithinWhatEq20AllowsThePapersMethod) {
  int first = 1, count = kScenes;
  if (const char* s = std::getenv("VOXFALL_PILE_SEED")) first = std::atoi(s), count = 1;
  int woken = 0;
  for (int seed = first; seed < first + count; ++seed) {
    const PileRun run = dropOntoPile(static_cast<std::uint64_t>(seed));
    EXPECT_LE(run.worstShare, 1.0)
        << "scene " << seed << ": " << run.worst << " (VOXFALL_PILE_SEED=" << seed << ")";
    EXPECT_EQ(run.overlappingReleases, 0u)
        << "scene " << seed << ": drop_height keeps births clear";
    woken += run.woken;
  }
  // The scenes do what they are for: piles fall asleep and landings wake them.
  EXPECT_GT(woken, 10 * count);
}

}  // namespace
}  // namespace vf

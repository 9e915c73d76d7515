// The paper's scenes release no body into another, under every run their figures make and at
// their own settings: so that a figure row's interpenetration measures the contact method, not
// a body born inside another. Two checks, at each body's start:
// - the bodies placed at t = 0: no leaf sphere of one touches a leaf sphere of another (brute
//   force over the leaves, independent of the narrow phase), and the true meshes do not
//   overlap (World::measure);
// - the bodies released later (emitters): the world counts a release whose spheres touch an
//   active body's (StepStats::overlappingReleases, tested in world_test); none may.
// Spheres are the stricter test: a mesh overlap is a sphere overlap (leaf spheres cover the
// surface), and touching spheres push bodies apart at the first step.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <ostream>
#include <string>
#include <vector>

#include "render/figures/paper_figures.h"
#include "sim/scene/scene.h"
#include "sim/shape/sphere_tree.h"
#include "sim/world.h"
#include "tests/support/test_world.h"

namespace vf {
namespace {

struct Case {
  std::string name;  // the test's name: where the run comes from
  fig::RunConfig run;
};

std::string stepName(double step) {
  if (step <= 0) return "eq20";
  char buf[32];
  std::snprintf(buf, sizeof buf, "1_%ld", std::lround(1 / step));
  return buf;
}

// Every figure run (full set) and every paper scene at its own settings (the CLI's, the golden
// suite's and the paper tests'; example 5 also at the paper's level 2).
std::vector<Case> cases() {
  std::vector<Case> out;
  for (const std::string& figure : fig::paperFigureNames())
    for (const fig::RunConfig& r : fig::paperFigureRuns(figure, false)) {
      const std::string method = r.collider == ColliderMethod::kPolygon ? "polygon" : "voxel";
      const std::string name = figure + "_" + r.scene + "_Lv" + std::to_string(r.level) + "_" +
                               method + "_" + stepName(r.step);
      if (std::none_of(out.begin(), out.end(), [&](const Case& c) { return c.name == name; }))
        out.push_back({name, r});
    }
  for (const char* scene : {"cubes", "blocks", "highpoly", "stack", "stack_10", "stack_20",
                            "crosses", "barrel", "cliff"})
    out.push_back({std::string(scene) + "_own_settings", {scene, 0, -1}});
  out.push_back({"crosses_Lv2_own_step", {"crosses", 2, -1}});
  return out;
}

// The scene as the case runs it; level 0 keeps the scene's level, step < 0 the scene's step.
SceneSpec caseSpec(const fig::RunConfig& r) {
  const std::string dir = test::sourcePath("scenes");
  if (r.level > 0 && r.step >= 0) return fig::figureRunSpec(dir, r);
  SceneSpec spec = loadScene(dir + "/" + r.scene + ".toml");
  if (r.level > 0) applyLevelOverride(spec, r.level);
  return spec;
}

// Leaf sphere centres of body i in its current pose, world frame.
std::vector<Vec3> leafCentres(const World& w, int i) {
  const BodyState& y = w.state(i);
  const Mat3 R = y.q.toRotationMatrix();
  std::vector<Vec3> out;
  for (const Vec3& c : w.shape(i).tree->leaves().centers) out.push_back(y.x + R * c);
  return out;
}

// How deep the leaf spheres of i and j reach into each other: the largest r_i + r_j - |p - q|
// over their centres p, q; 0 where none touch.
double leafOverlap(const World& w, int i, int j) {
  const double reach = w.shape(i).tree->leaves().radius + w.shape(j).tree->leaves().radius;
  const std::vector<Vec3> a = leafCentres(w, i), b = leafCentres(w, j);
  Eigen::AlignedBox3d boxB;
  for (const Vec3& q : b) boxB.extend(q);
  double deepest = 0;
  for (const Vec3& p : a) {
    if (boxB.exteriorDistance(p) >= reach) continue;  // touches none of j's spheres
    for (const Vec3& q : b) deepest = std::max(deepest, reach - (p - q).norm());
  }
  return deepest;
}

// gtest prints a failing case by its name.
void PrintTo(const Case& c, std::ostream* os) { *os << c.name; }

class PaperReleases : public ::testing::TestWithParam<Case> {};

TEST_P(PaperReleases, NoBodyStartsInsideAnother) {
  const SceneSpec spec = caseSpec(GetParam().run);
  BuiltScene built = buildScene(spec);
  World& w = *built.world;
  for (int i = 0; i < w.bodyCount(); ++i)
    for (int j = i + 1; j < w.bodyCount(); ++j)
      if (w.isActive(i) && w.isActive(j)) {
        EXPECT_EQ(leafOverlap(w, i, j), 0.0)
            << "bodies " << i << " and " << j << " start with their leaf spheres that deep (m) "
            << "in each other";
      }
  EXPECT_EQ(w.measure().maxPenetrationBodyBody, 0.0) << "true meshes overlap at t = 0";
  // Releases to come: bodies not active at t = 0.
  bool waiting = false;
  for (int i = 0; i < w.bodyCount(); ++i) waiting |= !w.isActive(i);
  while (waiting && w.nextStepEnd() <= spec.duration + 1e-9) {
    const StepStats& s = w.stepNext();
    EXPECT_EQ(s.overlappingReleases, 0u)
        << "a body released at t = " << w.time() << " s touches another body's spheres";
  }
}

INSTANTIATE_TEST_SUITE_P(FiguresAndScenes, PaperReleases, ::testing::ValuesIn(cases()),
                         [](const auto& info) { return info.param.name; });

}  // namespace
}  // namespace vf

// voxfall against Bullet on the paper's scenes, side by side in one process (built only when
// libbullet-dev is found). Run:
//   cmake --build build --target bullet_compare && build/tests/bench/bullet_compare [rounds]
// and the accuracy-cost frontier (frontier.h): bullet_compare --frontier ... CSV_DIR FIGURE_BASE
//
// For each scene: voxfall at level 4 with the eq.-20 step, once with the paper's method and
// once with contact reduction and sleeping; Bullet (btDiscreteDynamicsWorld, sequential-impulse
// solver, DBVT broad phase, one thread, fixed 1/60 s steps). Bullet gets the same meshes
// (convex hull for convex meshes, GImpact for non-convex ones; for the crosses also, as a second
// row, the compound of the cross's three convex pieces, Bullet's usual answer to a non-convex
// body, "a compound of 3 boxes"), masses and inertias, the same
// body-body and body-ground restitution and friction (Bullet multiplies the two bodies'
// coefficients: per-body values are chosen so that the products are the scene's), and the same
// spawn list: every body enters Bullet at the 1/60 s instant at which it is active in voxfall,
// with voxfall's state at that instant (so emitters and jitter are voxfall's); a body released
// at a drop height is placed by voxfall's rule on Bullet's own pile (bullet_runs.cpp).
// Time: thread CPU time spent stepping (no diagnostics), per simulated second; median over
// interleaved rounds. Interpenetration: one checker for both, World::measure's true-mesh test
// (collide/penetration.h), applied at every 1/60 s instant of an untimed identical run.
// The cliff is measured once with the scene's throw and once over 20 throws (the scene's seed
// and the 19 after it: the paper varies the throw's direction from run to run), each run's
// times, steps and awake bodies summed and its deepest interpenetration the largest.
// A second table splits each time into steps per simulated second (eq. 20's, or Bullet's 60)
// and CPU time per step; a third counts awake bodies, since a step's cost grows with the bodies
// it moves and both engines let bodies at rest sleep (voxfall's extensions; Bullet's default
// deactivation): awake body-steps per simulated second (voxfall: World's StepStats::awake;
// Bullet: the dynamic bodies isActive() before each step) and CPU time per awake body-step.
// A fourth table runs Bullet again at about eq. 20's rate (the whole number of steps per 1/60 s
// nearest to voxfall's with the extensions): the two engines at equal step counts, and how deep
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <stdexcept>
#include <string>
#include <vector>

#include "tests/bench/bullet_runs.h"
#include "tests/bench/frontier.h"

namespace {

using vf::bench::kFrame;
using vf::bench::median;
using vf::bench::Outcome;
using vf::bench::runBullet;
using vf::bench::runVoxfall;
using vf::bench::sceneAt;
using vf::bench::Spawn;

// times CPU time per step.
struct StepRow {
  std::string scene;
  double steps[4];      // per simulated s: paper, ext, ext + clearance, Bullet
  double usPerStep[4];  // median CPU us per step, the same order
  double awake[4];      // awake body-steps per simulated s, the same order
};

// A row of the fourth table: voxfall with the extensions against Bullet stepping about as often
// as eq. 20 does (eq. 20's steps per 1/60 s, rounded to a whole number of Bullet steps).
struct RateRow {
  std::string scene;
  int substeps;       // Bullet steps per 1/60 s
  double steps[2];    // per simulated s: ext, Bullet
  double cpu[2];      // median CPU s per simulated s, the same order
  double deepest[2];  // m, the same order
};

// A row of the tables: a scene, Bullet's shape for non-convex bodies, and how many throws (the
// scene's emitter seed and the ones after it).
struct Case {
  const char* label;
  const char* scene;
  bool compound;
  int throws;
};

// Several runs as one: times, steps and awake body-steps summed over the runs and divided by
// their simulated time in all; the deepest interpenetration the largest.
Outcome together(const std::vector<Outcome>& runs, const std::vector<vf::SceneSpec>& specs) {
  Outcome all;
  double duration = 0;
  for (std::size_t i = 0; i < runs.size(); ++i) {
    const double d = specs[i].duration;
    duration += d;
    all.cpuPerSimSecond += runs[i].cpuPerSimSecond * d;
    all.stepsPerSimSecond += runs[i].stepsPerSimSecond * d;
    all.awakePerSimSecond += runs[i].awakePerSimSecond * d;
    all.maxPenetration = std::max(all.maxPenetration, runs[i].maxPenetration);
  }
  all.cpuPerSimSecond /= duration;
  all.stepsPerSimSecond /= duration;
  all.awakePerSimSecond /= duration;
  return all;
}

int compare(int argc, char** argv) {
  const int rounds = argc > 1 ? std::max(1, std::atoi(argv[1])) : 5;
  const Case cases[] = {{"cubes", "cubes", false, 1},
                        {"blocks", "blocks", false, 1},
                        {"stack", "stack", false, 1},
                        {"crosses", "crosses", false, 1},
                        {"crosses, Bullet compound", "crosses", true, 1},
                        {"cliff", "cliff", false, 1},
                        {"cliff, 20 throws", "cliff", false, 20}};
  std::printf(
      "| scene | voxfall Lv4 paper (ms/sim s) | voxfall Lv4 +reduction+sleep | ext + clearance "
      "step | Bullet 1/60 s | paper / Bullet | ext / Bullet | ext + clearance / Bullet | deepest: "
      "Bullet, voxfall paper, ext, ext + clearance (mm) |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|\n");
  std::vector<StepRow> stepRows;
  std::vector<RateRow> rateRows;
  for (const Case& k : cases) {
    std::vector<vf::SceneSpec> paper, ext, clear;
    for (int t = 0; t < k.throws; ++t) {
      paper.push_back(sceneAt(k.scene, 4, false));
      ext.push_back(sceneAt(k.scene, 4, true));
      clear.push_back(sceneAt(k.scene, 4, true, true));
      for (auto* spec : {&paper.back(), &ext.back(), &clear.back()})
        for (vf::EmitterSpec& e : spec->emitters) e.seed += static_cast<std::uint64_t>(t);
    }
    // Round 0 checks and records the spawns; every round times all five, interleaved.
    std::vector<std::vector<std::vector<Spawn>>> spawns(k.throws);
    Outcome pv, ev, cv, bb, bq;
    std::vector<double> tp, te, tc, tb, tq;
    int substeps = 1;  // Bullet's steps per 1/60 s at eq. 20's rate, set in round 0
    for (int r = 0; r < rounds; ++r) {
      const bool check = r == 0;
      std::vector<Outcome> p, e, c, b, q;
      for (int t = 0; t < k.throws; ++t)
        p.push_back(runVoxfall(paper[t], check, check ? &spawns[t] : nullptr));
      for (int t = 0; t < k.throws; ++t) e.push_back(runVoxfall(ext[t], check, nullptr));
      const Outcome oe = together(e, ext);
      if (check)
        substeps = std::max(1, static_cast<int>(std::lround(oe.stepsPerSimSecond * kFrame)));
      for (int t = 0; t < k.throws; ++t) c.push_back(runVoxfall(clear[t], check, nullptr));
      for (int t = 0; t < k.throws; ++t)
        b.push_back(runBullet(paper[t], spawns[t], check, k.compound));
      for (int t = 0; t < k.throws; ++t)
        q.push_back(runBullet(paper[t], spawns[t], check, k.compound, substeps));
      const Outcome op = together(p, paper), oc = together(c, clear), ob = together(b, paper),
                    oq = together(q, paper);
      if (check) pv = op, ev = oe, cv = oc, bb = ob, bq = oq;
      tp.push_back(op.cpuPerSimSecond);
      te.push_back(oe.cpuPerSimSecond);
      tc.push_back(oc.cpuPerSimSecond);
      tb.push_back(ob.cpuPerSimSecond);
      tq.push_back(oq.cpuPerSimSecond);
    }
    const double p = median(tp), e = median(te), c = median(tc), b = median(tb), q = median(tq);
    std::printf(
        "| %s | %.1f | %.1f | %.1f | %.1f | %.2fx | %.2fx | %.2fx | %.0f, %.1f, %.1f, %.1f |\n",
        k.label, 1e3 * p, 1e3 * e, 1e3 * c, 1e3 * b, p / b, e / b, c / b, 1e3 * bb.maxPenetration,
        1e3 * pv.maxPenetration, 1e3 * ev.maxPenetration, 1e3 * cv.maxPenetration);
    std::fflush(stdout);
    StepRow row{
        k.label,
        {pv.stepsPerSimSecond, ev.stepsPerSimSecond, cv.stepsPerSimSecond, bb.stepsPerSimSecond},
        {},
        {pv.awakePerSimSecond, ev.awakePerSimSecond, cv.awakePerSimSecond, bb.awakePerSimSecond}};
    const double times[4] = {p, e, c, b};
    for (int i = 0; i < 4; ++i) row.usPerStep[i] = 1e6 * times[i] / row.steps[i];
    stepRows.push_back(row);
    rateRows.push_back({k.label, substeps, ev.stepsPerSimSecond, bq.stepsPerSimSecond, e, q,
                        ev.maxPenetration, bq.maxPenetration});
  }
  std::printf(
      "\n| scene | steps per simulated s: paper, ext, ext + clearance, Bullet | CPU us per step: "
      "paper, ext, ext + clearance, Bullet | ext / Bullet: steps, per step |\n");
  std::printf("|---|---|---|---|\n");
  for (const StepRow& r : stepRows)
    std::printf("| %s | %.0f, %.0f, %.0f, %.0f | %.1f, %.1f, %.1f, %.1f | %.2fx, %.2fx |\n",
                r.scene.c_str(), r.steps[0], r.steps[1], r.steps[2], r.steps[3], r.usPerStep[0],
                r.usPerStep[1], r.usPerStep[2], r.usPerStep[3], r.steps[1] / r.steps[3],
                r.usPerStep[1] / r.usPerStep[3]);
  std::printf(
      "\n| scene | awake bodies per step: ext, Bullet | awake body-steps per simulated s: ext, "
      "Bullet | CPU us per awake body-step: ext, Bullet | ext / Bullet: awake body-steps, per "
      "awake body-step |\n");
  std::printf("|---|---|---|---|---|\n");
  for (const StepRow& r : stepRows) {
    const double usPerAwake[2] = {r.usPerStep[1] * r.steps[1] / r.awake[1],
                                  r.usPerStep[3] * r.steps[3] / r.awake[3]};
    std::printf("| %s | %.2f, %.2f | %.0f, %.0f | %.2f, %.2f | %.2fx, %.2fx |\n", r.scene.c_str(),
                r.awake[1] / r.steps[1], r.awake[3] / r.steps[3], r.awake[1], r.awake[3],
                usPerAwake[0], usPerAwake[1], r.awake[1] / r.awake[3],
                usPerAwake[0] / usPerAwake[1]);
  }
  std::printf(
      "\n| scene | Bullet steps per 1/60 s | steps per simulated s: ext, Bullet | CPU ms per "
      "simulated s: ext, Bullet | ext / Bullet: time, per step | deepest (mm): ext, Bullet |\n");
  std::printf("|---|---|---|---|---|---|\n");
  for (const RateRow& r : rateRows)
    std::printf("| %s | %d | %.0f, %.0f | %.1f, %.1f | %.2fx, %.2fx | %.1f, %.0f |\n",
                r.scene.c_str(), r.substeps, r.steps[0], r.steps[1], 1e3 * r.cpu[0], 1e3 * r.cpu[1],
                r.cpu[0] / r.cpu[1], (r.cpu[0] / r.steps[0]) / (r.cpu[1] / r.steps[1]),
                1e3 * r.deepest[0], 1e3 * r.deepest[1]);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    if (argc > 1 && std::strcmp(argv[1], "--frontier") == 0)
      return vf::bench::frontierMain(argc - 1, argv + 1);
    return compare(argc, argv);
  } catch (const std::exception& e) {  // a scene that does not load, a wrong compound
    std::fprintf(stderr, "bullet_compare: error: %s\n", e.what());
    return 1;
  }
}

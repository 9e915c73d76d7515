// The runs behind bullet_compare: voxfall's, timed and checked, and Bullet's of the same scene
// with voxfall's spawn list. Bullet's headers stay in bullet_runs.cpp.
#pragma once

#include <string>
#include <vector>

#include "sim/scene/scene.h"

namespace vf::bench {

constexpr double kFrame = 1.0 / 60;  // instants at which spawns and the checker happen, s

// A body that enters the scene at a kFrame instant, with voxfall's state then.
struct Spawn {
  int id;
  vf::BodyState state;
};

struct Outcome {
  double cpuPerSimSecond = 0;
  double stepsPerSimSecond = 0;  // the same in every round (the runs are deterministic)
  double awakePerSimSecond = 0;  // awake body-steps per simulated s (the same in every round)
  double maxPenetration = 0;     // m, body-body and body-ground
};

// CPU time of the calling thread, s.
double threadSeconds();

// scenes/NAME.toml at one level for every shape, with contact reduction and sleeping when
// `extensions` (the fast method) and the clearance step rule (solve/time_step.h) instead of
// eq. 20 when `clearance`.
vf::SceneSpec sceneAt(const std::string& name, int level, bool extensions, bool clearance = false);

// voxfall: a timed run, then (if `spawns` or `check`) an untimed identical one that records
// the spawns and applies the checker (World::measure's true-mesh test) every kFrame.
Outcome runVoxfall(const vf::SceneSpec& spec, bool check, std::vector<std::vector<Spawn>>* spawns);

// voxfall in one run, timed and checked: the clock runs only inside World::advanceTo, the
// checker and the spawn list are taken between the timed calls.
Outcome runChecked(const vf::SceneSpec& spec, bool check, std::vector<std::vector<Spawn>>* spawns);

// Bullet (btDiscreteDynamicsWorld, one thread) on the same shapes and contact coefficients,
// each body entering at its spawn instant; `substeps` fixed steps per kFrame, only the steps
// timed; the checker at every kFrame instant when `check`. `compound`: a non-convex shape as
// the compound of its convex pieces instead of GImpact.
Outcome runBullet(const vf::SceneSpec& spec, const std::vector<std::vector<Spawn>>& spawns,
                  bool check, bool compound, int substeps = 1);

double median(std::vector<double> v);

// The Bullet linked in, "3.24".
std::string bulletVersion();

}  // namespace vf::bench

// Islands (sim/solve/islands.h) come from this step's contacts; everything runs in body-id
// order over the fixed contact order, so who sleeps and when is a function of the state alone:
// the trajectory stays deterministic.
//
// Why island-wide: a body resting on another one that still moves must not freeze under it.
// Why the momenta are zeroed: a sleeping body is not integrated; any residual velocity would
// be lost anyway, and zero makes waking up start from rest.
#include "sim/solve/sleep.h"

#include <algorithm>

#include "sim/shape/shape.h"
#include "sim/solve/islands.h"

namespace vf {

std::vector<int> wakeTouched(const std::vector<Contact>& contacts, std::vector<BodyInfo>& bodies) {
  std::vector<int> woken;
  auto wakeIsland = [&](int island) {
    for (std::size_t i = 0; i < bodies.size(); ++i)
      if (bodies[i].sleeping && bodies[i].sleepIsland == island) {
        bodies[i].sleeping = false;
        bodies[i].restTime = 0;
        woken.push_back(static_cast<int>(i));
      }
  };
  for (const Contact& c : contacts) {
    if (c.b == kGround) continue;
    const BodyInfo &a = bodies[c.a], &b = bodies[c.b];
    if (a.sleeping && b.moves()) wakeIsland(a.sleepIsland);
    if (b.sleeping && a.moves()) wakeIsland(b.sleepIsland);
  }
  std::sort(woken.begin(), woken.end());
  return woken;
}

int updateSleep(const std::vector<Contact>& contacts, std::vector<BodyInfo>& bodies,
                std::vector<BodyState>& states, double dt, const SleepSettings& settings) {
  const int n = static_cast<int>(bodies.size());
  // Scratch reused from step to step (per thread: ensembles step worlds on several).
  static thread_local std::vector<char> touching, ready;
  static thread_local std::vector<int> root;
  // Only a supported body rests: one slow at the top of a throw, or drifting slowly through
  // empty space, is not at rest and must not freeze there.
  touching.assign(n, 0);
  for (const Contact& c : contacts) {
    touching[c.a] = 1;
    if (c.b != kGround) touching[c.b] = 1;
  }
  for (int i = 0; i < n; ++i) {
    BodyInfo& b = bodies[i];
    if (!b.moves()) continue;
    if (!touching[i]) {
      b.restTime = 0;
      continue;
    }
    const double fastest = velocityOf(b, states[i]).norm() +
                           0.5 * b.shape->diameter * angularVelocityOf(b, states[i]).norm();
    b.restTime = fastest < settings.speed ? b.restTime + dt : 0.0;
  }
  islandRoots(contacts, bodies, root);
  // An island is ready if every moving member has rested long enough.
  ready.assign(n, 1);
  for (int i = 0; i < n; ++i)
    if (bodies[i].moves() && bodies[i].restTime < settings.time) ready[root[i]] = 0;
  int slept = 0;
  for (int i = 0; i < n; ++i) {
    BodyInfo& b = bodies[i];
    if (!b.moves() || !ready[root[i]]) continue;
    b.sleeping = true;
    b.sleepIsland = root[i];
    states[i].P.setZero();
    states[i].L.setZero();
    ++slept;
  }
  return slept;
}

}  // namespace vf

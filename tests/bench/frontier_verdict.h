// The accuracy-cost goal against Bullet, as a pure function of two frontiers: at every depth
// Bullet reaches, voxfall's cheapest setting that is at least as accurate takes at most a given
// share of Bullet's time.
#pragma once

#include <string>
#include <vector>

namespace vf::bench {

// One setting of one engine on one scene: its cost and its accuracy, both from one checker.
struct FrontierPoint {
  std::string setting;    // "Lv 4, eq. 20, paper", "1/240 s", ...
  double msPerSimSecond;  // CPU ms of stepping per simulated s
  double deepestMm;       // deepest true-mesh interpenetration over the run, mm
};

// The verdict at one Bullet point.
struct PointVerdict {
  FrontierPoint bullet;
  bool matched = false;   // some voxfall point is at most as deep as `bullet`
  FrontierPoint voxfall;  // the cheapest such point (ties: the shallower, then the first)
  double ratio = 0;       // voxfall's time over Bullet's (when matched)
  bool pass = false;      // matched and voxfall's time <= maxRatio x Bullet's
};

// One verdict per Bullet point, in Bullet's order. A Bullet point no voxfall point matches fails.
std::vector<PointVerdict> frontierVerdict(const std::vector<FrontierPoint>& voxfall,
                                          const std::vector<FrontierPoint>& bullet,
                                          double maxRatio);

// Whether every Bullet point passes (false for none: a goal with no evidence is not met).
bool goalMet(const std::vector<PointVerdict>& verdicts);

}  // namespace vf::bench

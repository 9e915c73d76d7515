#include "tests/bench/frontier_verdict.h"

namespace vf::bench {

std::vector<PointVerdict> frontierVerdict(const std::vector<FrontierPoint>& voxfall,
                                          const std::vector<FrontierPoint>& bullet,
                                          double maxRatio) {
  std::vector<PointVerdict> out;
  for (const FrontierPoint& b : bullet) {
    PointVerdict v;
    v.bullet = b;
    for (const FrontierPoint& p : voxfall) {
      if (p.deepestMm > b.deepestMm) continue;  // less accurate than Bullet here
      const bool cheaper =
          p.msPerSimSecond < v.voxfall.msPerSimSecond ||
          (p.msPerSimSecond == v.voxfall.msPerSimSecond && p.deepestMm < v.voxfall.deepestMm);
      if (!v.matched || cheaper) v.voxfall = p;
      v.matched = true;
    }
    if (v.matched) {
      v.ratio = v.voxfall.msPerSimSecond / b.msPerSimSecond;
      v.pass = v.voxfall.msPerSimSecond <= maxRatio * b.msPerSimSecond;
    }
    out.push_back(v);
  }
  return out;
}

bool goalMet(const std::vector<PointVerdict>& verdicts) {
  if (verdicts.empty()) return false;
  for (const PointVerdict& v : verdicts)
    if (!v.pass) return false;
  return true;
}

}  // namespace vf::bench

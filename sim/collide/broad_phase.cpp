// All-pairs bounding-sphere test. The scenes of the paper have at most a few dozen bodies, for
// which O(n^2) sphere tests cost less than maintaining a spatial structure; a sweep or grid
// belongs here if scenes grow to thousands of bodies.
#include "sim/collide/broad_phase.h"

namespace vf {

void findPairs(const std::vector<BodyInfo>& bodies, const std::vector<BodyState>& states,
               std::vector<BodyPair>& pairs) {
  const int n = static_cast<int>(bodies.size());
  for (int a = 0; a < n; ++a) {
    if (!bodies[a].active) continue;
    const double ra = bodies[a].shape->tree->boundingRadius;
    for (int b = a + 1; b < n; ++b) {
      if (!bodies[b].active || (bodies[a].isStatic && bodies[b].isStatic)) continue;
      const double reach = ra + bodies[b].shape->tree->boundingRadius;
      if ((states[a].x - states[b].x).squaredNorm() < reach * reach) pairs.push_back({a, b});
    }
  }
}

}  // namespace vf

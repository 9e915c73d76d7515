#include "sim/solve/islands.h"

#include <algorithm>
#include <numeric>

namespace vf {

void islandRoots(const std::vector<Contact>& contacts, const std::vector<BodyInfo>& bodies,
                 std::vector<int>& root) {
  const int n = static_cast<int>(bodies.size());
  root.resize(n);
  std::iota(root.begin(), root.end(), 0);
  // Union-find with path halving; the lower root wins, so a root is its island's lowest id.
  auto find = [&root](int i) {
    while (root[i] != i) i = root[i] = root[root[i]];
    return i;
  };
  for (const Contact& c : contacts) {
    if (c.b == kGround || !bodies[c.a].moves() || !bodies[c.b].moves()) continue;
    const int ra = find(c.a), rb = find(c.b);
    if (ra != rb) root[std::max(ra, rb)] = std::min(ra, rb);
  }
  for (int i = 0; i < n; ++i) root[i] = find(i);
}

}  // namespace vf

// Test oracle: does a segment meet an axis-aligned square? Liang and Barsky's clipping, written
// apart from the ensemble's cell walk (sim/ensemble/ensemble.cpp, cellsOnSegment).
#pragma once

#include <algorithm>

namespace vf::test {

// Segment (px, py) - (qx, qy) against the closed square [x0, x1] x [y0, y1].
inline bool segmentMeetsSquare(double px, double py, double qx, double qy, double x0, double x1,
                               double y0, double y1) {
  double t0 = 0, t1 = 1;
  const double dx = qx - px, dy = qy - py;
  const double p[4] = {-dx, dx, -dy, dy};
  const double q[4] = {px - x0, x1 - px, py - y0, y1 - py};
  for (int k = 0; k < 4; ++k) {
    if (p[k] == 0) {
      if (q[k] < 0) return false;
    } else {
      const double t = q[k] / p[k];
      if (p[k] < 0)
        t0 = std::max(t0, t);
      else
        t1 = std::min(t1, t);
      if (t0 > t1) return false;
    }
  }
  return true;
}

}  // namespace vf::test

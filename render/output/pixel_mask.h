// Rectangles of a frame that a comparison ignores (a time overlay, a clock, a logo): pixels in
// any of them count neither as differing nor as compared.
#pragma once

#include <vector>

namespace vf {

struct PixelRect {
  int x = 0;  // left column, pixels from the left edge
  int y = 0;  // top row, pixels from the top edge
  int width = 0;
  int height = 0;

  bool contains(int px, int py) const {
    return px >= x && py >= y && px - x < width && py - y < height;
  }
};

using PixelMask = std::vector<PixelRect>;

inline bool masked(const PixelMask& mask, int px, int py) {
  for (const PixelRect& r : mask)
    if (r.contains(px, py)) return true;
  return false;
}

}  // namespace vf

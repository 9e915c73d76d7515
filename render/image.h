// A rendered frame in memory: 8-bit sRGB-encoded RGB, rows top to bottom (the order of PNG
// and of video frames, the opposite of glReadPixels), and optionally an 8-bit alpha plane
// (straight, not premultiplied: 0 transparent, 255 opaque) for PNGs with a transparent
// background.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace vf {

struct Image {
  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> rgb;    // width * height * 3 bytes, top row first
  std::vector<std::uint8_t> alpha;  // width * height bytes, top row first; empty: opaque

  Image() = default;
  Image(int w, int h) : width(w), height(h), rgb(static_cast<std::size_t>(w) * h * 3, 0) {}
  // The three bytes of pixel (x, y), y = 0 at the top.
  const std::uint8_t* pixel(int x, int y) const {
    return rgb.data() + (static_cast<std::size_t>(y) * width + x) * 3;
  }
  std::uint8_t* pixel(int x, int y) {
    return rgb.data() + (static_cast<std::size_t>(y) * width + x) * 3;
  }
};

}  // namespace vf

// The colour map of hazard maps: viridis, perceptually uniform (lightness rises steadily from
// dark purple to yellow, so equal steps in value look like equal steps in colour, and it reads
// in grey and for the common colour-vision deficiencies).
#pragma once

#include <array>
#include <cstdint>

namespace vf {

struct Rgb8 {
  std::uint8_t r = 0, g = 0, b = 0;
  bool operator==(const Rgb8&) const = default;
};

// The 256 entries of viridis as 8-bit sRGB, from dark (index 0) to light (255).
const std::array<Rgb8, 256>& viridisTable();

// The colour of `t` in [0, 1] (clamped; NaN gives entry 0): entry min(255, floor(256 t)), the
// lookup of a 256-entry listed colour map (matplotlib's convention).
Rgb8 viridis(double t);

}  // namespace vf

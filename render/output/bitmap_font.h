// Text drawn into an Image with a small built-in 5 x 7 bitmap font, so that labels in pictures
// (filmstrip times, the regression compare picture) look the same on every machine and need no
// font library. Digits, capital letters, 't', 's', 'x', 'm', 'k' and " .:=-%()/_".
#pragma once

#include <array>
#include <cstdint>
#include <string>

#include "render/image.h"

namespace vf {

constexpr int kGlyphWidth = 5;
constexpr int kGlyphHeight = 7;

// True when every character of `text` has a glyph.
bool fontCovers(const std::string& text);

// Width in pixels of `text` drawn at `scale` pixels per font pixel (a column of space between
// glyphs, none after the last).
int textWidth(const std::string& text, int scale);

// Draws `text` with its top-left corner at (x, y), clipped to the image. A character without a
// glyph is a programming error (asserted).
void drawText(Image& image, int x, int y, const std::string& text, int scale,
              std::array<std::uint8_t, 3> colour);

}  // namespace vf

#include "render/figures/filmstrip.h"

#include <algorithm>
#include <array>
#include <cstdio>
#include <cstring>

#include "sim/core/error.h"

namespace vf::fig {
namespace {

// 5 x 7 glyphs, one row per byte, bit 4 = leftmost column.
struct Glyph {
  char c;
  std::array<std::uint8_t, 7> rows;
};
constexpr std::array<Glyph, 15> kFont{{
    {'0', {0x0E, 0x11, 0x13, 0x15, 0x19, 0x11, 0x0E}},
    {'1', {0x04, 0x0C, 0x04, 0x04, 0x04, 0x04, 0x0E}},
    {'2', {0x0E, 0x11, 0x01, 0x02, 0x04, 0x08, 0x1F}},
    {'3', {0x1F, 0x02, 0x04, 0x02, 0x01, 0x11, 0x0E}},
    {'4', {0x02, 0x06, 0x0A, 0x12, 0x1F, 0x02, 0x02}},
    {'5', {0x1F, 0x10, 0x1E, 0x01, 0x01, 0x11, 0x0E}},
    {'6', {0x06, 0x08, 0x10, 0x1E, 0x11, 0x11, 0x0E}},
    {'7', {0x1F, 0x01, 0x02, 0x04, 0x08, 0x08, 0x08}},
    {'8', {0x0E, 0x11, 0x11, 0x0E, 0x11, 0x11, 0x0E}},
    {'9', {0x0E, 0x11, 0x11, 0x0F, 0x01, 0x02, 0x0C}},
    {'.', {0x00, 0x00, 0x00, 0x00, 0x00, 0x0C, 0x0C}},
    {'t', {0x08, 0x08, 0x1C, 0x08, 0x08, 0x09, 0x06}},
    {'s', {0x00, 0x00, 0x0E, 0x10, 0x0E, 0x01, 0x1E}},
    {'=', {0x00, 0x00, 0x1F, 0x00, 0x1F, 0x00, 0x00}},
    {' ', {0, 0, 0, 0, 0, 0, 0}},
}};
constexpr int kScale = 3;             // px per font pixel
constexpr int kAdvance = 6 * kScale;  // glyph width plus one column of space

const Glyph& glyph(char c) {
  for (const Glyph& g : kFont)
    if (g.c == c) return g;
  VF_ASSERT(false && "filmstrip label character outside the built-in font");
  return kFont.back();
}

void drawText(Image& img, int x0, int y0, const std::string& text) {
  for (std::size_t i = 0; i < text.size(); ++i) {
    const Glyph& g = glyph(text[i]);
    for (int row = 0; row < 7; ++row)
      for (int col = 0; col < 5; ++col) {
        if (!(g.rows[row] & (0x10 >> col))) continue;
        for (int dy = 0; dy < kScale; ++dy)
          for (int dx = 0; dx < kScale; ++dx) {
            const int x = x0 + static_cast<int>(i) * kAdvance + col * kScale + dx;
            const int y = y0 + row * kScale + dy;
            if (x >= 0 && y >= 0 && x < img.width && y < img.height)
              std::memset(img.pixel(x, y), 0x20, 3);  // dark grey text
          }
      }
  }
}

}  // namespace

FrameSlot filmstripSlot(int index, int columns, int frameWidth, int frameHeight) {
  const int col = index % columns, row = index / columns;
  return {kFilmstripGap + col * (frameWidth + kFilmstripGap),
          kFilmstripGap + row * (kFilmstripLabelBand + frameHeight + kFilmstripGap) +
              kFilmstripLabelBand};
}

Image composeFilmstrip(const std::vector<Image>& frames, const std::vector<std::string>& labels,
                       int columns) {
  VF_ASSERT(!frames.empty() && frames.size() == labels.size() && columns > 0);
  const int w = frames[0].width, h = frames[0].height;
  const int n = static_cast<int>(frames.size());
  columns = std::min(columns, n);
  const int rows = (n + columns - 1) / columns;
  Image out(kFilmstripGap + columns * (w + kFilmstripGap),
            kFilmstripGap + rows * (kFilmstripLabelBand + h + kFilmstripGap));
  std::fill(out.rgb.begin(), out.rgb.end(), 0xFF);
  for (int i = 0; i < n; ++i) {
    VF_ASSERT(frames[i].width == w && frames[i].height == h);
    const FrameSlot s = filmstripSlot(i, columns, w, h);
    for (int y = 0; y < h; ++y)
      std::memcpy(out.pixel(s.x, s.y + y), frames[i].pixel(0, y), static_cast<std::size_t>(w) * 3);
    // Label centred over the frame, vertically centred in the band.
    const int textWidth = static_cast<int>(labels[i].size()) * kAdvance - kScale;
    drawText(out, s.x + (w - textWidth) / 2,
             s.y - kFilmstripLabelBand + (kFilmstripLabelBand - 7 * kScale) / 2, labels[i]);
  }
  return out;
}

std::string timeLabel(double seconds) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.4f", seconds);
  std::string s = buf;
  while (s.back() == '0') s.pop_back();
  if (s.back() == '.') s.pop_back();
  return "t = " + s + " s";
}

}  // namespace vf::fig

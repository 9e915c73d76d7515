#include "render/figures/filmstrip.h"

#include <algorithm>
#include <array>
#include <cstdio>
#include <cstring>

#include "render/output/bitmap_font.h"
#include "sim/core/error.h"

namespace vf::fig {
namespace {

constexpr int kScale = 3;  // px per font pixel

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
    const int width = textWidth(labels[i], kScale);
    drawText(out, s.x + (w - width) / 2,
             s.y - kFilmstripLabelBand + (kFilmstripLabelBand - kGlyphHeight * kScale) / 2,
             labels[i], kScale, {0x20, 0x20, 0x20});  // dark grey text
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

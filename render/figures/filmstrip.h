// Filmstrips (the paper's figs. 20-26): frames side by side in one image, each under a label
// with its time. The frames are copied pixel for pixel; labels are drawn in a band above each
// frame with the small built-in bitmap font (render/output/bitmap_font.h), so no font library
// is needed and the image is the same on every machine.
#pragma once

#include <string>
#include <vector>

#include "render/image.h"

namespace vf::fig {

// Where frame i lies in a filmstrip of `count` frames of w x h in `columns` columns: cells in
// reading order, each a label band of kFilmstripLabelBand px then the frame, kFilmstripGap px
// between cells and around the image.
constexpr int kFilmstripLabelBand = 30;  // px
constexpr int kFilmstripGap = 8;         // px
struct FrameSlot {
  int x = 0, y = 0;  // top-left pixel of the frame (below its label)
};
FrameSlot filmstripSlot(int index, int columns, int frameWidth, int frameHeight);

// The filmstrip of `frames` (all the same size) with `labels` (one per frame, characters of
// "0123456789.ts= " only) in `columns` columns, on a white background.
Image composeFilmstrip(const std::vector<Image>& frames, const std::vector<std::string>& labels,
                       int columns);

// "t = 0.5 s": a time label with up to 4 decimals, trailing zeros removed.
std::string timeLabel(double seconds);

}  // namespace vf::fig

// PNG files through libpng (the only file that includes png.h is png_writer.cpp): frames out,
// and golden or user frames back in for `voxfall diff` and `voxfall regress`.
#pragma once

#include <string>

#include "render/output/frame_sink.h"
#include "render/output/output_file.h"

namespace vf {

// Blender's frame-number convention: the last run of '#' in `pattern` becomes `frame`
// zero-padded to the run's length ("f_####.png", 7 -> "f_0007.png"; a number wider than the
// run is written whole). A pattern without '#' is returned unchanged.
std::string expandFramePattern(const std::string& pattern, int frame);

// Writes an 8-bit RGB PNG (tagged sRGB) to `path` through an OutputFile (temporary name, then
// a rename) under `rules`. On failure throws InputError(path, reason) and leaves nothing behind.
void writePng(const std::string& path, const Image& image,
              const OutputRules& rules = replaceOutputs());

// Reads any PNG (grey, palette, RGB, with or without alpha, 8 or 16 bits) as 8-bit sRGB RGB,
// so frames from other tools compare with voxfall's own; alpha is composited onto black.
// Throws InputError(path, reason) when the file is missing or not a readable PNG.
Image readPng(const std::string& path);

// One PNG per frame: expandFramePattern(pattern, index).
class PngSequenceWriter final : public FrameSink {
 public:
  PngSequenceWriter(std::string pattern, OutputRules rules)
      : pattern_(std::move(pattern)), rules_(std::move(rules)) {}
  void write(int index, const Image& image) override;
  void finish() override {}  // every frame is complete once written
  int framesWritten() const override { return frames_; }
  std::string path() const override { return pattern_; }

 private:
  std::string pattern_;
  OutputRules rules_;
  int frames_ = 0;
};

}  // namespace vf

// PNG files: frames and pictures out (our own PNG chunks around a zlib stream from
// libdeflate), and golden or user frames back in through libpng for `voxfall diff` and
// `voxfall regress`. png_writer.cpp is the only file that includes png.h or libdeflate.h.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "render/output/frame_sink.h"
#include "render/output/output_file.h"

namespace vf {

// Blender's frame-number convention: the last run of '#' in `pattern` becomes `frame`
// zero-padded to the run's length ("f_####.png", 7 -> "f_0007.png"; a number wider than the
// run is written whole). A pattern without '#' is returned unchanged.
std::string expandFramePattern(const std::string& pattern, int frame);

// How hard the compressor works on a PNG: libdeflate's level 1 for frames, its level 6 (zlib's
// default) for single pictures. Either way the rows are stored unfiltered: the ordered dither
// of the present pass repeats every 4 pixels, which deflate matches where a row filter would
// scramble it, so on voxfall's frames no filter is both faster and smaller than libpng's
// adaptive filters (docs/output-formats.md has the measurements).
enum class PngCompression { small, fast };

// The bytes of an 8-bit PNG of `image` (tagged sRGB): RGB, or RGBA when the image has an alpha
// plane. The same pixels give the same bytes on every run and thread. Throws
// InputError(where, reason) if the compressor cannot be made.
std::vector<std::uint8_t> encodePng(const Image& image, PngCompression compression,
                                    const std::string& where);

// Writes an 8-bit RGB (or RGBA) PNG (tagged sRGB) to `path` through an OutputFile (temporary
// name, then a rename) under `rules`. On failure throws InputError(path, reason) and leaves
// nothing behind.
void writePng(const std::string& path, const Image& image,
              const OutputRules& rules = replaceOutputs(),
              PngCompression compression = PngCompression::small);

// Reads any PNG (grey, palette, RGB, with or without alpha, 8 or 16 bits) as 8-bit sRGB RGB,
// so frames from other tools compare with voxfall's own; alpha is composited onto black.
// Throws InputError(path, reason) when the file is missing or not a readable PNG.
Image readPng(const std::string& path);

// One PNG per frame: expandFramePattern(pattern, index), compressed PngCompression::fast.
// write() hands the frame to worker threads and returns, so frames are compressed while the
// next ones are drawn; the files are written in frame order by the caller's thread (in write()
// and finish()), so an interrupted run leaves frames first..k with no gaps. A frame's bytes
// depend on its pixels alone, never on the thread count.
class PngSequenceWriter final : public FrameSink {
 public:
  // `threads` compressing workers; 0: one per processor, at most kMaxPngThreads.
  PngSequenceWriter(std::string pattern, OutputRules rules, int threads = 0);
  // Frames accepted but not yet written are dropped (finish() writes them).
  ~PngSequenceWriter() override;
  // Queues the frame (waiting while 2 frames per worker are queued) and writes the frames
  // whose compression has finished. Throws InputError for the first frame that failed.
  void write(int index, const Image& image) override;
  // Waits for every queued frame and writes it; throws the first failure.
  void finish() override;
  // Frames accepted so far (all written once finish() has returned).
  int framesWritten() const override;
  std::string path() const override;
  int threads() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

inline constexpr int kMaxPngThreads = 8;

}  // namespace vf

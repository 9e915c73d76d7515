// Where rendered frames go: one interface, a PNG sequence writer (png_writer.h) and an MP4
// encoder (video_encoder.h). Every output is written under a temporary name and renamed into
// place when complete, so a failed run never leaves a half-written file under the real name.
#pragma once

#include <memory>
#include <string>

#include "render/image.h"
#include "render/output/output_file.h"

namespace vf {

class FrameSink {
 public:
  virtual ~FrameSink() = default;
  // Adds the frame with simulation frame number `index` (t = index / fps). Indices increase.
  // Throws InputError on an I/O failure.
  virtual void write(int index, const Image& image) = 0;
  // Completes the output; afterwards everything is in place under its final name.
  virtual void finish() = 0;
  // Frames accepted so far.
  virtual int framesWritten() const = 0;
  // The output path or pattern, for messages.
  virtual std::string path() const = 0;
};

// What an MP4 needs beyond the frames.
struct VideoSettings {
  int width = 1280;  // pixels, even
  int height = 720;  // pixels, even
  double fps = 30;   // frames per second of simulation time
  int crf = 18;      // x264 constant rate factor, 0 (lossless) .. 51
};

enum class OutputKind {
  mp4,          // "*.mp4": H.264 video
  pngSequence,  // a path with a run of '#': one PNG per frame
  png,          // "*.png" without '#': one PNG, only for a single frame
};

// The kind of output a path asks for. Throws InputError for anything else.
OutputKind outputKind(const std::string& path);

// Opens the sink for `path` (see OutputKind) that will receive frames first..last; the video
// settings are used for MP4 only. Every file it will write is checked against `rules` now
// (output_file.h), so an existing frame is refused before any work. Throws InputError when the
// path or settings cannot work (unknown suffix, a single-file PNG for several frames, odd MP4
// size, unwritable folder, an existing output without -y, an input of the run).
std::unique_ptr<FrameSink> openFrameSink(const std::string& path, const VideoSettings& video,
                                         int first, int last, const OutputRules& rules);

}  // namespace vf

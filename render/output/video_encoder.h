// MP4 output: H.264 (libx264) in an MP4 container through libavcodec/libavformat, yuv420p
// BT.709. The only file that includes libav headers is video_encoder.cpp.
//
// Timing: codec time base 1/fps, pts = the simulation frame index, and the MP4 track's
// timescale set to the fps numerator, so frame k is shown at exactly t = k / fps.
// Determinism: x264 runs with exactly one thread (its output depends on the thread count),
// the muxer and encoder run bit-exact (no library version strings) and no creation time is
// written, so the same frames give the same bytes on every run and machine with the same
// library versions.
#pragma once

#include <memory>
#include <string>

#include "render/output/frame_sink.h"

namespace vf {

class VideoEncoder final : public FrameSink {
 public:
  // Opens an OutputFile for `path` under `rules` (output_file.h). Width and height must be even
  // (yuv420p stores colour at half resolution in both directions): odd sizes are rejected with
  // InputError rather than padded or cropped, so the video is always the size asked for.
  VideoEncoder(const std::string& path, const VideoSettings& settings, const OutputRules& rules);
  // Not finished (an error or interruption unwound the caller): the frames written so far are
  // finalised into a playable file under the real name; with no frames, nothing is left.
  ~VideoEncoder() override;

  void write(int index, const Image& image) override;
  // Flushes the encoder, writes the index (moved to the front: +faststart) and renames.
  void finish() override;
  int framesWritten() const override;
  std::string path() const override;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace vf

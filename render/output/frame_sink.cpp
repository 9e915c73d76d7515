#include "render/output/frame_sink.h"

#include <cctype>

#include "render/output/png_writer.h"
#include "render/output/video_encoder.h"
#include "sim/core/error.h"

namespace vf {
namespace {

bool endsWith(const std::string& s, const std::string& suffix) {
  if (s.size() < suffix.size()) return false;
  for (std::size_t i = 0; i < suffix.size(); ++i) {
    const char c = s[s.size() - suffix.size() + i];
    if (std::tolower(static_cast<unsigned char>(c)) != suffix[i]) return false;
  }
  return true;
}

}  // namespace

OutputKind outputKind(const std::string& path) {
  if (path.find('#') != std::string::npos) {
    if (!endsWith(path, ".png")) {
      throw InputError(path, "a frame pattern with '#' must end in .png (e.g. frame_####.png)");
    }
    return OutputKind::pngSequence;
  }
  if (endsWith(path, ".mp4")) return OutputKind::mp4;
  if (endsWith(path, ".png")) return OutputKind::png;
  throw InputError(path,
                   "unknown output kind: use a .mp4 file, or a PNG pattern with '#' for the "
                   "frame number (e.g. out/frames/frame_####.png)");
}

std::unique_ptr<FrameSink> openFrameSink(const std::string& path, const VideoSettings& video,
                                         int first, int last, const OutputRules& rules) {
  const int frameCount = last - first + 1;
  switch (outputKind(path)) {
    case OutputKind::mp4:
      return std::make_unique<VideoEncoder>(path, video, rules);
    case OutputKind::pngSequence:
      for (int k = first; k <= last; ++k) checkOutputPath(expandFramePattern(path, k), rules);
      return std::make_unique<PngSequenceWriter>(path, rules);
    case OutputKind::png:
      if (frameCount != 1) {
        throw InputError(path, "a single .png holds one frame but " + std::to_string(frameCount) +
                                   " are to be rendered: put '#' in the name for the frame "
                                   "number, or pick one frame with --frames N:N");
      }
      checkOutputPath(path, rules);
      return std::make_unique<PngSequenceWriter>(path, rules);
  }
  return nullptr;  // unreachable: every kind is handled
}

}  // namespace vf

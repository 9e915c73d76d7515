#include "render/run/render_run.h"

#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <utility>

#include "render/gl/gl_context.h"
#include "render/gl/renderer.h"
#include "render/output/frame_sink.h"
#include "render/run/run_input.h"
#include "render/run/run_report.h"
#include "render/scene_playback.h"
#include "sim/bake.h"
#include "sim/core/error.h"
#include "sim/recorder.h"
#include "sim/run_guard.h"

namespace vf {
namespace {

struct FrameRange {
  int first = 0;
  int last = 0;
};

int frameNumber(const std::string& s, int fallback, const std::string& text) {
  if (s.empty()) return fallback;
  std::size_t used = 0;
  int value = -1;
  try {
    value = std::stoi(s, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used != s.size() || value < 0)
    throw InputError("--frames", "'" + text + "' is not A:B with frame numbers >= 0");
  return value;
}

// "A:B" (inclusive), "A:" (to the end), ":B" (from 0), "N" (one frame) -> [first, last],
// checked against the scene's frames 0 .. count - 1.
FrameRange parseFrames(const std::string& text, int count) {
  FrameRange r{0, count - 1};
  if (!text.empty()) {
    const std::size_t colon = text.find(':');
    if (colon == std::string::npos) {
      r.first = r.last = frameNumber(text, 0, text);
    } else {
      r.first = frameNumber(text.substr(0, colon), 0, text);
      r.last = frameNumber(text.substr(colon + 1), count - 1, text);
    }
  }
  if (r.first > r.last || r.last >= count) {
    throw InputError("--frames", "'" + text + "' is outside the scene's frames 0:" +
                                     std::to_string(count - 1) + " (first <= last)");
  }
  return r;
}

// The output: path and kind, checked against the run's rules (-y, -n, inputs) now. Without -o
// the render replaces its own default output, so that the same command can be run again (as the
// README's first command is); a path the user names needs -y. From here on a signal only raises
// a flag, so the temporary file the sink creates is always removed or finalised, never left
// behind. The sink checks the size (an MP4 needs even sides) and every file it will write.
std::unique_ptr<FrameSink> openOutput(const RenderRequest& r, const RunInput& input,
                                      const FrameRange& range) {
  const SceneSpec& spec = input.spec;
  const bool defaultOutput = r.output.empty();
  const std::string path = defaultOutput ? "out/" + spec.name + ".mp4" : r.output;
  const bool replaceDefault = defaultOutput && !r.neverOverwrite;
  const OutputRules rules =
      runOutputRules(spec, r.input, r.overwrite || replaceDefault, r.neverOverwrite);
  watchForStop();
  // An unknown kind fails now, and so does a transparent background asked of an MP4.
  if (outputKind(path) == OutputKind::mp4 && spec.output.alpha)
    throw InputError(r.drawing.alpha ? "--alpha" : r.input,
                     "an MP4 (H.264) has no alpha channel: write a PNG sequence for a "
                     "transparent background, e.g. -o out/" +
                         spec.name + "/frame_####.png");
  if (replaceDefault && std::filesystem::exists(path) && !r.quiet)
    std::fprintf(stderr, "voxfall: replacing %s, render's default output (-n keeps it)\n",
                 path.c_str());
  VideoSettings video;
  video.width = spec.output.width;
  video.height = spec.output.height;
  video.fps = spec.fps;
  video.crf = spec.output.crf;
  return openFrameSink(path, video, range.first, range.last, rules);
}

gl::RenderSettings glSettings(const RenderRequest& r, const SceneSpec& spec) {
  gl::RenderSettings settings;
  settings.width = spec.output.width;
  settings.height = spec.output.height;
  settings.shaderDir = r.shaders;
  settings.alpha = spec.output.alpha;
  return settings;
}

// What the playback did, for the summary.
struct Played {
  std::optional<RunSummary> summary;  // none: an ensemble's bake (Bake::summary)
  int frames = 0;                     // the frames of the scene at the output's rate
  std::size_t bakedBodies = 0;        // the bodies of a bake; 0 for a scene
  DrawnFrames drawn;
};

// The two passes of render/scene_playback.h: the scene simulated (or the bake read), then frames
// A..B drawn into the sink. None when stopped before the first frame was written.
std::optional<Played> play(RunInput& input, gl::Renderer& renderer, FrameSink& sink,
                           const FrameRange& range, bool quiet) {
  const SceneSpec& spec = input.spec;
  const auto stop = [] { return stopRequested() != 0; };
  Played played;
  std::optional<ScenePlayback> playback;
  if (input.bake) {
    played.bakedBodies = input.bake->bodies.size();
    input.bake->scene = spec;  // fps, size and quality from the command line
    playback.emplace(std::make_shared<const Bake>(std::move(*input.bake)), spec.output.width,
                     spec.output.height);
  } else {
    playback.emplace(spec, spec.output.width, spec.output.height);
  }
  try {
    if (!playback->simulate(!quiet, stop)) return std::nullopt;
  } catch (const RunawayError& e) {  // nothing drawn yet: the sink removes its temporary file
    throw InputError(spec.path, e.what());
  }
  played.drawn = playback->drawFrames(renderer, sink, range.first, range.last, !quiet, stop);
  if (played.drawn.last < range.first) return std::nullopt;
  if (const RunSummary* run = playback->summary()) played.summary = *run;
  played.frames = playback->frameCount();
  return played;
}

// The run's summary: a bake without a run summary is an ensemble's subset (Bake::summary), whose
// bodies are realisations each stepped alone, so it says that instead.
void summarise(const Played& played, const SceneSpec& spec, const std::string& path) {
  if (played.summary) return printSummary(stdout, spec.name, *played.summary);
  std::printf(
      "%s: %d frames of %zu ensemble realisations from the bake %s (each was stepped "
      "alone by `voxfall ensemble`: no run summary or checksum)\n",
      spec.name.c_str(), played.frames, played.bakedBodies, path.c_str());
}

void reportDrawing(const SceneSpec& spec, const std::string& method, const DrawnFrames& d,
                   const std::string& path) {
  const int drawn = d.last - d.first + 1;
  std::printf("  rendered %s (%dx%d, %s) in %.2f s: %.2f frames/s, %.0f%% of the pixels redrawn\n",
              d.span().c_str(), spec.output.width, spec.output.height, method.c_str(), d.seconds,
              d.seconds > 0 ? drawn / d.seconds : 0.0, 100 * d.redrawn / drawn);
  std::printf("  output %s\n", path.c_str());
}

}  // namespace

RunStatus runRender(const RenderRequest& r) {
  RunInput input = loadRunInput(r.input, r.overrides, r.drawing);
  const SceneSpec& spec = input.spec;
  const FrameRange range =
      parseFrames(r.frames, Recorder::frameCountFor(spec.fps, spec.duration, spec.output.speed));
  const std::unique_ptr<FrameSink> sink = openOutput(r, input, range);
  // GL context and shaders: a missing library or a shader typo fails here, in seconds.
  const gl::Backend backend = gl::parseBackend(r.gl);
  const std::string backendName = gl::backendName(backend);
  const auto context = gl::createContext(backend);
  gl::Renderer renderer(*context, glSettings(r, spec));
  const std::string method = renderer.antialiasing() + ", " + backendName;

  const std::optional<Played> played = play(input, renderer, *sink, range, r.quiet);
  if (!played) return stoppedWithNothingWritten();
  if (const int stop = stopRequested()) {
    std::fprintf(stderr, "voxfall: interrupted; %s written to %s (playable, incomplete)\n",
                 played->drawn.span().c_str(), sink->path().c_str());
    summarise(*played, spec, r.input);
    return RunStatus::stopped(stop);
  }
  summarise(*played, spec, r.input);
  if (input.bake && played->summary)
    std::printf("  steps simulated: 0 (states from the bake %s)\n", r.input.c_str());
  reportDrawing(spec, method, played->drawn, sink->path());
  return RunStatus::done();
}

}  // namespace vf

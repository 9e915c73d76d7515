#include "render/run/render_run.h"

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <tuple>
#include <utility>

#include "render/gl/gl_context.h"
#include "render/gl/renderer.h"
#include "render/gl/shader_program.h"
#include "render/output/frame_sink.h"
#include "render/progress.h"
#include "render/run/run_output.h"
#include "render/scene_playback.h"
#include "sim/bake.h"
#include "sim/core/error.h"
#include "sim/recorder.h"
#include "sim/run_guard.h"
#include "sim/shape/sphere_tree.h"

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

std::string frameSpan(int first, int last) {
  return first == last ? "frame " + std::to_string(first)
                       : "frames " + std::to_string(first) + ".." + std::to_string(last);
}

// The scene (or bake) and the options that change it. A bake's physics is fixed: its steps are
// recorded, so only what drawing reads (fps, size, quality) can change.
RunInput loadInput(const RenderRequest& r) {
  RunInput input = loadRunInput(r.input, r.overrides);
  SceneSpec& spec = input.spec;
  applyFrameRateOverrides(spec, r.fps, r.speed);
  if (r.size) std::tie(spec.output.width, spec.output.height) = *r.size;
  if (r.crf) spec.output.crf = *r.crf;
  if (r.alpha) spec.output.alpha = true;
  if (r.overlay) {
    spec.output.overlayTime = r.overlay->time;
    spec.output.overlayScale = r.overlay->scale;
  }
  if (!r.camera.empty()) {
    try {
      selectCamera(spec, r.camera);
    } catch (const InputError& e) {
      // A bake carries its scene's cameras: name the file the user gave, not the scene's.
      if (!input.bake) throw;
      throw InputError(r.input, e.message());
    }
  }
  return input;
}

// The output: path and kind, checked against the run's rules (-y, -n, inputs) now. Without -o
// the render replaces its own default output, so that the same command can be run again (as the
// README's first command is); a path the user names needs -y. From here on a signal only raises
// a flag, so the temporary file the sink creates is always removed or finalised, never left
// behind. The sink checks the size (an MP4 needs even sides) and every file it will write.
std::unique_ptr<FrameSink> openOutput(const RenderRequest& r, const SceneSpec& spec,
                                      const FrameRange& range) {
  const bool defaultOutput = r.output.empty();
  const std::string path = defaultOutput ? "out/" + spec.name + ".mp4" : r.output;
  // An unknown kind fails now, and so does a transparent background asked of an MP4.
  if (outputKind(path) == OutputKind::mp4 && spec.output.alpha)
    throw InputError(r.alpha ? "--alpha" : r.input,
                     "an MP4 (H.264) has no alpha channel: write a PNG sequence for a "
                     "transparent background, e.g. -o out/" +
                         spec.name + "/frame_####.png");
  const bool replaceDefault = defaultOutput && !r.neverOverwrite;
  const OutputRules rules =
      runOutputRules(spec, r.input, r.overwrite || replaceDefault, r.neverOverwrite);
  if (replaceDefault && std::filesystem::exists(path) && !r.quiet)
    std::fprintf(stderr, "voxfall: replacing %s, render's default output (-n keeps it)\n",
                 path.c_str());
  VideoSettings video;
  video.width = spec.output.width;
  video.height = spec.output.height;
  video.fps = spec.fps;
  video.crf = spec.output.crf;
  watchForStop();
  return openFrameSink(path, video, range.first, range.last, rules);
}

gl::RenderSettings glSettings(const RenderRequest& r, const SceneSpec& spec) {
  gl::RenderSettings settings;
  settings.width = spec.output.width;
  settings.height = spec.output.height;
  settings.shaderDir = gl::findShaderDir(r.shaders);
  settings.alpha = spec.output.alpha;
  return settings;
}

// What drawing the frames measured.
struct Drawing {
  double seconds = 0;  // drawing and writing the frames
  double redrawn = 0;  // sum over frames of the share of pixels drawn
  int lastDone = 0;    // the last frame written
};

// Frames A..B into the sink until done or stopped; `d` holds what was done even when drawing
// or writing a frame throws.
void drawLoop(ScenePlayback& playback, gl::Renderer& renderer, FrameSink& sink,
              const FrameRange& range, const std::string& name, bool quiet, Drawing& d) {
  Progress progress(name + " (drawing)", range.last - range.first + 1, !quiet);
  const auto drawStart = std::chrono::steady_clock::now();
  Image image;
  for (int k = range.first; k <= range.last && !stopRequested(); ++k) {
    const auto start = std::chrono::steady_clock::now();
    playback.draw(renderer, k, image);
    d.redrawn += renderer.redrawnFraction();
    sink.write(k, image);
    d.seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    d.lastDone = k;
    const int drawn = k - range.first + 1;
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - drawStart).count();
    char detail[64];
    std::snprintf(detail, sizeof detail, "frame %d, %.2f frames/s", k,
                  seconds > 0 ? drawn / seconds : 0.0);
    progress.update(drawn, detail);
  }
  progress.finish();
}

// The frames, finalised; false when stopped before the first (the sink's destructor removes its
// temporary file). On an error the frames so far are kept: the sink finalises them (an MP4
// stays playable) and main() reports the error itself.
bool drawFrames(ScenePlayback& playback, gl::Renderer& renderer, FrameSink& sink,
                const FrameRange& range, const std::string& name, bool quiet, Drawing& d) {
  d.lastDone = range.first - 1;
  try {
    drawLoop(playback, renderer, sink, range, name, quiet, d);
    if (stopRequested() && sink.framesWritten() == 0) return false;
    sink.finish();
  } catch (const std::exception&) {
    if (sink.framesWritten() > 0) {
      try {
        sink.finish();
        std::fprintf(stderr, "voxfall: incomplete output: %s written to %s\n",
                     frameSpan(range.first, d.lastDone).c_str(), sink.path().c_str());
      } catch (const std::exception&) {
      }
    }
    throw;
  }
  return true;
}

// The run's summary: a bake without a run summary is an ensemble's subset (Bake::summary), whose
// bodies are realisations each stepped alone, so it says that instead.
void summarise(const ScenePlayback& playback, const SceneSpec& spec, const std::string& input,
               std::size_t bakedBodies) {
  if (const RunSummary* run = playback.summary()) return printSummary(stdout, spec.name, *run);
  std::printf(
      "%s: %d frames of %zu ensemble realisations from the bake %s (each was stepped "
      "alone by `voxfall ensemble`: no run summary or checksum)\n",
      spec.name.c_str(), playback.frameCount(), bakedBodies, input.c_str());
}

void reportDrawing(const RenderRequest& r, const SceneSpec& spec, const FrameRange& range,
                   const gl::Renderer& renderer, const Drawing& d, const std::string& path) {
  const int drawn = range.last - range.first + 1;
  std::printf(
      "  rendered %s (%dx%d, %s, %s) in %.2f s: %.2f frames/s, %.0f%% of the pixels "
      "redrawn\n",
      frameSpan(range.first, range.last).c_str(), spec.output.width, spec.output.height,
      renderer.antialiasing().c_str(), gl::backendName(gl::parseBackend(r.gl)), d.seconds,
      d.seconds > 0 ? drawn / d.seconds : 0.0, 100 * d.redrawn / drawn);
  std::printf("  output %s\n", path.c_str());
}

// Pass 1 of the playback: the world simulated through every frame (a bake is read).
std::unique_ptr<ScenePlayback> simulateInput(RunInput& input, bool quiet) {
  const SceneSpec& spec = input.spec;
  std::unique_ptr<ScenePlayback> playback;
  if (input.bake) {
    input.bake->scene = spec;  // fps, size and quality from the command line
    playback = std::make_unique<ScenePlayback>(std::make_shared<const Bake>(std::move(*input.bake)),
                                               spec.output.width, spec.output.height);
  } else {
    playback = std::make_unique<ScenePlayback>(spec, spec.output.width, spec.output.height);
  }
  try {
    if (!playback->simulate(!quiet, [] { return stopRequested() != 0; })) return nullptr;
  } catch (const RunawayError& e) {  // nothing drawn yet: the sink removes its temporary file
    throw InputError(spec.path, e.what());
  }
  return playback;
}

}  // namespace

RunStatus runRender(const RenderRequest& r) {
  RunInput input = loadInput(r);
  const SceneSpec& spec = input.spec;
  const int frameCount = Recorder::frameCountFor(spec.fps, spec.duration, spec.output.speed);
  const FrameRange range = parseFrames(r.frames, frameCount);
  std::unique_ptr<FrameSink> sink = openOutput(r, spec, range);
  // GL context and shaders: a missing library or a shader typo fails here, in seconds.
  auto context = gl::createContext(gl::parseBackend(r.gl));
  gl::Renderer renderer(*context, glSettings(r, spec));

  const bool fromBake = input.bake.has_value();
  const std::size_t bakedBodies = fromBake ? input.bake->bodies.size() : 0;
  const std::unique_ptr<ScenePlayback> playback = simulateInput(input, r.quiet);
  if (!playback) return stoppedWithNothingWritten();
  VF_ASSERT(playback->frameCount() == frameCount);
  Drawing d;
  if (!drawFrames(*playback, renderer, *sink, range, spec.name, r.quiet, d))
    return stoppedWithNothingWritten();
  if (const int stop = stopRequested()) {
    std::fprintf(stderr, "voxfall: interrupted; %s written to %s (playable, incomplete)\n",
                 frameSpan(range.first, d.lastDone).c_str(), sink->path().c_str());
    summarise(*playback, spec, r.input, bakedBodies);
    return RunStatus::stopped(stop);
  }
  summarise(*playback, spec, r.input, bakedBodies);
  if (fromBake && playback->summary())
    std::printf("  steps simulated: 0 (states from the bake %s)\n", r.input.c_str());
  reportDrawing(r, spec, range, renderer, d, sink->path());
  return RunStatus::done();
}

}  // namespace vf

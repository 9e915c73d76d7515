// voxfall render SCENE: simulates a scene from t = 0 and draws frames A..B (all by default) to
// an MP4 or a PNG sequence.
//
// Order matters for the user, as in `simulate`: cheap checks first (scene file, options, output
// path, GL context and shaders), the expensive shape building and stepping last, so a typo or a
// missing GL library never costs a long run.
//
// The frames come from a ScenePlayback (scene_playback.h): the scene is simulated whole,
// then drawn.
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <atomic>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "render/cli/commands.h"
#include "render/cli/options.h"
#include "render/cli/run_output.h"
#include "render/draw_list.h"
#include "render/gl/gl_context.h"
#include "render/gl/renderer.h"
#include "render/gl/shader_program.h"
#include "render/output/frame_sink.h"
#include "render/progress.h"
#include "render/scene_playback.h"
#include "sim/bake.h"
#include "sim/core/error.h"
#include "sim/recorder.h"
#include "sim/run_guard.h"
#include "sim/scene/scene.h"
#include "sim/shape/sphere_tree.h"

namespace vf::cli {
namespace {

struct RenderOptions {
  std::string scene;
  std::string output;                       // "": out/<scene name>.mp4
  std::string frames;                       // "A:B", "A:", ":B" or "N"
  std::optional<std::pair<int, int>> size;  // --size WxH
  std::optional<double> fps;
  std::optional<double> speed;           // --speed X
  bool alpha = false;                    // --alpha
  std::optional<OverlayChoice> overlay;  // --overlay LIST
  SceneOverrides overrides;              // --level, --step, --collider, run limits, --repair
  std::optional<int> crf;
  std::string gl = "osmesa";
  std::string shaders;
  std::string camera;  // [cameras.NAME]; "": the scene's [camera]
  bool quiet = false;
  bool overwrite = false;       // -y
  bool neverOverwrite = false;  // -n
};

struct FrameRange {
  int first = 0;
  int last = 0;
};

// "A:B" (inclusive), "A:" (to the end), ":B" (from 0), "N" (one frame) -> [first, last],
// checked against the scene's frames 0 .. count - 1.
FrameRange parseFrames(const std::string& text, int count) {
  FrameRange r{0, count - 1};
  if (!text.empty()) {
    auto number = [&](const std::string& s, int fallback) {
      if (s.empty()) return fallback;
      std::size_t used = 0;
      int value = -1;
      try {
        value = std::stoi(s, &used);
      } catch (const std::exception&) {
        used = 0;
      }
      if (used != s.size() || value < 0) {
        throw InputError("--frames", "'" + text + "' is not A:B with frame numbers >= 0");
      }
      return value;
    };
    const std::size_t colon = text.find(':');
    if (colon == std::string::npos) {
      r.first = r.last = number(text, 0);
    } else {
      r.first = number(text.substr(0, colon), 0);
      r.last = number(text.substr(colon + 1), count - 1);
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

int runRender(const RenderOptions& o) {
  // 1. The scene (or bake) and the options that change it. A bake's physics is fixed: its
  // steps are recorded, so only what drawing reads (fps, size, quality) can change.
  RunInput input = loadRunInput(o.scene, o.overrides);
  SceneSpec& spec = input.spec;
  std::optional<Bake>& bake = input.bake;
  applyFrameRateOverrides(spec, o.fps, o.speed);
  if (o.size) std::tie(spec.output.width, spec.output.height) = *o.size;
  if (o.crf) spec.output.crf = *o.crf;
  if (o.alpha) spec.output.alpha = true;
  if (o.overlay) {
    spec.output.overlayTime = o.overlay->time;
    spec.output.overlayScale = o.overlay->scale;
  }
  if (!o.camera.empty()) {
    try {
      selectCamera(spec, o.camera);
    } catch (const InputError& e) {
      // A bake carries its scene's cameras: name the file the user gave, not the scene's.
      if (!bake) throw;
      throw InputError(o.scene, e.message());
    }
  }
  const int width = spec.output.width, height = spec.output.height;
  const int frameCount = Recorder::frameCountFor(spec.fps, spec.duration, spec.output.speed);
  const FrameRange range = parseFrames(o.frames, frameCount);

  // 2. The output: path and kind, checked against the run's rules (-y, -n, inputs) now.
  // Without -o the render replaces its own default output, so that the same command can be
  // run again (as the README's first command is); a path the user names needs -y.
  const bool defaultOutput = o.output.empty();
  const std::string path = defaultOutput ? "out/" + spec.name + ".mp4" : o.output;
  // An unknown kind fails now, and so does a transparent background asked of an MP4.
  if (outputKind(path) == OutputKind::mp4 && spec.output.alpha)
    throw InputError(o.alpha ? "--alpha" : o.scene,
                     "an MP4 (H.264) has no alpha channel: write a PNG sequence for a "
                     "transparent background, e.g. -o out/" +
                         spec.name + "/frame_####.png");
  const bool replaceDefault = defaultOutput && !o.neverOverwrite;
  const OutputRules rules =
      runOutputRules(spec, o.scene, o.overwrite || replaceDefault, o.neverOverwrite);
  if (replaceDefault && std::filesystem::exists(path) && !o.quiet)
    std::fprintf(stderr, "voxfall: replacing %s, render's default output (-n keeps it)\n",
                 path.c_str());

  VideoSettings video;
  video.width = width;
  video.height = height;
  video.fps = spec.fps;
  video.crf = spec.output.crf;
  // From here on a signal only raises a flag (output_file.h), so the temporary file the sink
  // creates is always removed or finalised, never left behind. The sink checks the size (an
  // MP4 needs even sides) and every file it will write before any work.
  installStopHandlers();
  std::unique_ptr<FrameSink> sink = openFrameSink(path, video, range.first, range.last, rules);

  // 3. GL context and shaders (a missing library or a shader typo fails here, in seconds).
  auto context = gl::createContext(gl::parseBackend(o.gl));
  gl::RenderSettings settings;
  settings.width = width;
  settings.height = height;
  settings.shaderDir = gl::findShaderDir(o.shaders);
  settings.alpha = spec.output.alpha;
  gl::Renderer renderer(*context, settings);

  // 4. The world, simulated through every frame.
  std::optional<ScenePlayback> played;
  // A bake without a run summary is an ensemble's subset (Bake::summary): its bodies are
  // realisations, each stepped alone, so it says that instead.
  const std::size_t bakedBodies = bake ? bake->bodies.size() : 0;
  auto summarise = [&](const ScenePlayback& playback) {
    if (const RunSummary* run = playback.summary()) return printSummary(stdout, spec.name, *run);
    std::printf(
        "%s: %d frames of %zu ensemble realisations from the bake %s (each was stepped "
        "alone by `voxfall ensemble`: no run summary or checksum)\n",
        spec.name.c_str(), playback.frameCount(), bakedBodies, o.scene.c_str());
  };
  if (bake) {
    bake->scene = spec;  // fps, size and quality from the command line
    played.emplace(std::make_shared<const Bake>(std::move(*bake)), width, height);
  } else {
    played.emplace(spec, width, height);
  }
  ScenePlayback& playback = *played;
  VF_ASSERT(playback.frameCount() == frameCount);
  bool simulated = false;
  try {
    simulated = playback.simulate(!o.quiet, [] { return stopSignal() != 0; });
  } catch (const RunawayError& e) {  // nothing drawn yet: the sink removes its temporary file
    throw InputError(spec.path, e.what());
  }
  if (!simulated) {
    std::fprintf(stderr, "voxfall: interrupted before the first frame; no output written\n");
    return 128 + stopSignal();  // the sink's destructor removes its temporary file
  }

  // 5. Frames A..B.
  Progress progress(spec.name + " (drawing)", range.last - range.first + 1, !o.quiet);
  const auto drawStart = std::chrono::steady_clock::now();
  Image image;
  double renderSeconds = 0;
  double redrawn = 0;  // sum over frames of the share of pixels drawn
  int lastDone = range.first - 1;
  try {
    for (int k = range.first; k <= range.last && !stopSignal(); ++k) {
      const auto start = std::chrono::steady_clock::now();
      playback.draw(renderer, k, image);
      redrawn += renderer.redrawnFraction();
      sink->write(k, image);
      renderSeconds +=
          std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      lastDone = k;
      const int drawn = k - range.first + 1;
      const double seconds =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - drawStart).count();
      char detail[64];
      std::snprintf(detail, sizeof detail, "frame %d, %.2f frames/s", k,
                    seconds > 0 ? drawn / seconds : 0.0);
      progress.update(drawn, detail);
    }
    progress.finish();
    if (stopSignal() && sink->framesWritten() == 0) {
      std::fprintf(stderr, "voxfall: interrupted before the first frame; no output written\n");
      return 128 + stopSignal();  // the sink's destructor removes its temporary file
    }
    sink->finish();
  } catch (const std::exception&) {
    // Keep what was made: the sink finalises the frames so far (an MP4 stays playable), and
    // main() reports the error itself with exit code 1.
    progress.finish();
    if (sink->framesWritten() > 0) {
      try {
        sink->finish();
        std::fprintf(stderr, "voxfall: incomplete output: %s written to %s\n",
                     frameSpan(range.first, lastDone).c_str(), sink->path().c_str());
      } catch (const std::exception&) {
      }
    }
    throw;
  }
  if (stopSignal()) {
    std::fprintf(stderr, "voxfall: interrupted; %s written to %s (playable, incomplete)\n",
                 frameSpan(range.first, lastDone).c_str(), sink->path().c_str());
    summarise(playback);
    return 128 + stopSignal();  // 130 for SIGINT, 143 for SIGTERM, as the shell would say
  }

  const int drawn = range.last - range.first + 1;
  summarise(playback);
  if (bake && playback.summary())
    std::printf("  steps simulated: 0 (states from the bake %s)\n", o.scene.c_str());
  std::printf(
      "  rendered %s (%dx%d, %s, %s) in %.2f s: %.2f frames/s, %.0f%% of the pixels "
      "redrawn\n",
      frameSpan(range.first, range.last).c_str(), width, height, renderer.antialiasing().c_str(),
      gl::backendName(gl::parseBackend(o.gl)), renderSeconds,
      renderSeconds > 0 ? drawn / renderSeconds : 0.0, 100 * redrawn / drawn);
  std::printf("  output %s\n", sink->path().c_str());
  return 0;
}

}  // namespace

int renderToFile(const std::string& input, const std::string& output, bool overwrite,
                 bool neverOverwrite, bool quiet) {
  RenderOptions o;
  o.scene = input;
  o.output = output;
  o.overwrite = overwrite;
  o.neverOverwrite = neverOverwrite;
  o.quiet = quiet;
  return runRender(o);
}

void addRenderCommand(CLI::App& app, int& exitCode) {
  // Owned by the callback: CLI11 fills it during parse, after this function has returned.
  auto o = std::make_shared<RenderOptions>();
  CLI::App* sub = app.add_subcommand(
      "render",
      "Simulate a scene (or read a bake) and render its frames to an MP4 or a PNG sequence");
  sub->add_option("INPUT", o->scene, "scene file (TOML) or bake (voxfall simulate --bake)")
      ->required()
      ->type_name("");
  sub->add_option("-o,--output", o->output,
                  "OUT.mp4 (H.264), or a PNG pattern whose '#' run becomes the frame number, "
                  "e.g. out/cubes/frame_####.png (default: out/<scene name>.mp4)")
      ->type_name("OUT");
  sub->add_option("--frames", o->frames,
                  "frames to draw, A:B inclusive (30:30 is one frame; the simulation still "
                  "starts at t = 0)")
      ->type_name("A:B");
  addSizeOption(*sub, o->size);
  sub->add_option("--fps", o->fps, "frames per second (overrides [simulation] fps)")
      ->check(finiteNumberIn(0.001, 1000.0))
      ->type_name("N");
  addSpeedOption(*sub, o->speed);
  addFrameLookOptions(*sub, o->alpha, o->overlay);
  addPhysicsOptions(*sub, o->overrides, " (scenes only)");
  addThreadsOption(*sub, o->overrides, " (scenes only)");
  sub->add_option("--crf", o->crf, "H.264 quality, 0..51, lower is better (default: 18)")
      ->check(CLI::Range(0, 51))
      ->type_name("N");
  sub->add_option("--gl", o->gl, "OpenGL backend: osmesa (default) or egl (surfaceless)")
      ->check(CLI::IsMember({"osmesa", "egl"}))
      ->type_name("osmesa|egl");
  sub->add_option("--shaders", o->shaders,
                  "folder of the GLSL sources (default: next to the binary, else the source "
                  "tree's shaders/)")
      ->type_name("DIR");
  sub->add_option("--camera", o->camera,
                  "which of the scene's cameras to use: a [cameras.NAME] table, or 'camera' for "
                  "[camera] (the default)")
      ->type_name("NAME");
  sub->add_flag("--quiet,-q", o->quiet, "no progress line on stderr");
  addOverwriteFlags(*sub, o->overwrite, o->neverOverwrite);
  sub->callback([o, &exitCode] { exitCode = runRender(*o); });
}

}  // namespace vf::cli

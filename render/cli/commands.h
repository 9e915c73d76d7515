// The voxfall command's subcommands. Each adds itself to the CLI11 app and returns the
// process exit code through the callback's `exitCode`.
#pragma once

#include <functional>
#include <memory>
#include <vector>

#include "render/draw_list.h"
#include "render/image.h"
#include "sim/recorder.h"
#include "sim/scene/scene.h"

namespace CLI {
class App;
}

namespace vf::gl {
class Context;
}

namespace vf::cli {

// voxfall simulate SCENE [--csv FILE] [--summary FILE] [--level N] [--step S|auto] [--quiet]
void addSimulateCommand(CLI::App& app, int& exitCode);
// voxfall render SCENE [-o OUT] [--frames A:B] [--size WxH] [--fps N] [--level N] [--crf N]
void addRenderCommand(CLI::App& app, int& exitCode);
// voxfall diff EXPECTED ACTUAL [--threshold T] [--max-fraction F] [--out DIFF]
void addDiffCommand(CLI::App& app, int& exitCode);
// voxfall regress SUITE_DIR [-o REPORT_DIR] [--update]
void addRegressCommand(CLI::App& app, int& exitCode);

// The two passes of `voxfall render` (render_command.cpp says why there are two), shared with
// `voxfall regress` so a golden frame is exactly the frame `render --frames k:k` draws.
class ScenePlayback {
 public:
  // Builds the world (meshes, shapes, sphere trees) for frames of width x height pixels.
  ScenePlayback(const SceneSpec& spec, int width, int height);
  ~ScenePlayback();
  ScenePlayback(const ScenePlayback&) = delete;
  ScenePlayback& operator=(const ScenePlayback&) = delete;

  // Pass 1, called once: simulates frames 0 .. frameCount() - 1 from t = 0, keeping each
  // frame's poses and folding them into the automatic camera. `stop` is asked before each
  // frame; returns false when it said stop. `progress`: a progress line on stderr for long runs.
  bool simulate(bool progress, const std::function<bool()>& stop = {});
  // Frames k = 0 .. floor(duration * fps).
  int frameCount() const;
  // The run's numbers (checksum included), complete after simulate().
  const RunSummary& summary() const;
  // Pass 2: what to draw for frame k (after simulate()).
  DrawList drawList(int k);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// Frames of a scene drawn in-process, as `voxfall render SCENE --frames k:k` would draw them
// at spec.output's size: the images in the order of `frames` and the run's summary.
struct RenderedFrames {
  std::vector<Image> images;
  RunSummary summary;
};
// Simulates `spec` and draws `frames` (each in 0 .. frame count - 1, else InputError) with the
// current GL `context` and the shaders in `shaderDir`. `adjust`, when given, may change each
// draw list before it is drawn: a test aid (e.g. turning the sun to prove goldens catch it).
RenderedFrames renderSceneFrames(const SceneSpec& spec, const std::vector<int>& frames,
                                 gl::Context& context, const std::string& shaderDir,
                                 const std::function<void(DrawList&)>& adjust = {});

}  // namespace vf::cli

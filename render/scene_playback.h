// A scene simulated once and drawn frame by frame: the two passes of `voxfall render`
// (scene_playback.cpp says why there are two), shared with `voxfall regress` so that a golden
// frame is exactly the frame `render --frames k:k` draws.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "render/draw_list.h"
#include "render/image.h"
#include "sim/bake.h"
#include "sim/recorder.h"
#include "sim/scene/scene.h"

namespace vf::gl {
class Context;
class Renderer;
}  // namespace vf::gl

namespace vf {

class FrameSink;
struct Heightfield;

// What pass 2 measured (ScenePlayback::drawFrames).
struct DrawnFrames {
  int first = 0;       // the first frame asked for
  int last = -1;       // the last frame written; first - 1 when none was
  double seconds = 0;  // drawing and writing the frames
  double redrawn = 0;  // sum over frames of the share of pixels the renderer drew
  // "frame 7" or "frames 0..60": the frames written, for messages.
  std::string span() const;
};

class ScenePlayback {
 public:
  // Builds the world (meshes, shapes, sphere trees) for frames of width x height pixels.
  ScenePlayback(const SceneSpec& spec, int width, int height);
  // Plays a bake (sim/bake.h) instead: no world, no step; frames at bake->scene.fps (which
  // may differ from the fps of the run that made it).
  ScenePlayback(std::shared_ptr<const Bake> bake, int width, int height);
  ~ScenePlayback();
  ScenePlayback(const ScenePlayback&) = delete;
  ScenePlayback& operator=(const ScenePlayback&) = delete;

  // Pass 1, called once: simulates frames 0 .. frameCount() - 1 from t = 0, keeping each
  // frame's poses and folding them into the automatic camera. `stop` is asked before each
  // frame; returns false when it said stop. `progress`: a progress line on stderr for long runs.
  bool simulate(bool progress, const std::function<bool()>& stop = {});
  // Drawn frames k = 0 .. floor(duration * fps / speed) ([output] speed; 1: the scene's frames).
  int frameCount() const;
  // The simulated time of drawn frame k: k speed / fps, s (Recorder::frameTimeFor).
  double frameTime(int k) const;
  // The run's numbers (checksum included), complete after simulate(); a bake's are the run's
  // that made it, and null for a bake without a run (an ensemble's subset, Bake::summary).
  const RunSummary* summary() const;
  // Steps this playback simulated: the run's, or 0 for a bake.
  std::uint64_t stepsSimulated() const;
  // Pass 2: what to draw for frame k (after simulate()).
  DrawList drawList(int k);
  // Frame k drawn by `renderer` into `out`, with the overlays [output] asks for (overlay.h).
  // `adjust`, when given, may change the draw list first (a test aid).
  void draw(gl::Renderer& renderer, int k, Image& out,
            const std::function<void(DrawList&)>& adjust = {});
  // Pass 2 for an output: frames first..last drawn into `sink`, in order, and the sink
  // finalised. `stop` is asked before each frame; stopped before the first, the sink is left
  // unfinished (its destructor removes the temporary file) and nothing is written; stopped
  // later, the frames so far are finalised (an MP4 stays playable). An error while drawing or
  // writing finalises the frames written, says so on stderr and is rethrown. `progress`: a
  // progress line on stderr.
  DrawnFrames drawFrames(gl::Renderer& renderer, FrameSink& sink, int first, int last,
                         bool progress, const std::function<bool()>& stop = {});
  // Every body (shape, colour) posed at frame k (after simulate()), for export.
  std::vector<BodyView> bodiesAt(int k);
  // The terrain in world coordinates, as drawn, and its smooth vertex normals; null without
  // one.
  std::shared_ptr<const TriMesh> terrainMesh() const;
  std::shared_ptr<const std::vector<Vec3>> terrainNormals() const;
  // The picture draped on the terrain ([ground] texture), resampled over the DEM's extent;
  // null without one.
  std::shared_ptr<const DrapeImage> terrainTexture() const;
  // The terrain's heightfield (its CRS and the offset added to its coordinates); null without.
  std::shared_ptr<const Heightfield> terrain() const;
  // Per body id: the name of its [shapes] entry.
  const std::vector<std::string>& shapeNames() const;
  // The scene's [output] (size, speed, alpha, overlays), with command-line overrides.
  const OutputSpec& output() const;

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
// Draws `frames` of a bake at width x height, as `voxfall render BAKE --frames k:k --size WxH`
// would; a frame outside the bake's is an InputError naming `where`.
std::vector<Image> renderBakeFrames(std::shared_ptr<const Bake> bake, const std::string& where,
                                    const std::vector<int>& frames, int width, int height,
                                    gl::Context& context, const std::string& shaderDir);

}  // namespace vf

// Two passes. The whole scene is simulated first (frame k = the state at exactly t = k / fps),
// keeping every frame's body poses and folding them into the automatic camera framing; then
// frames A..B are drawn from the kept poses. Why not draw while stepping: the automatic camera
// must frame every body over the whole clip to stay still (a camera that re-frames as bodies
// fly apart zooms and pans for no reason), and frame k must look the same whether rendered in
// a full run or alone with --frames k:k (figures, golden-frame tests). The price is simulating
// past B when B is not the last frame; simulation is cheap next to drawing (a few ms per frame
// against ~200 ms), and the summary then carries the same checksum as `voxfall simulate`.
// `voxfall regress` draws its frames through this too (renderSceneFrames), so a golden frame
// is byte for byte what `render` writes.
#include "render/scene_playback.h"

#include <chrono>
#include <cstdio>
#include <optional>

#include "render/gl/gl_context.h"
#include "render/gl/renderer.h"
#include "render/output/frame_sink.h"
#include "render/overlay.h"
#include "render/progress.h"
#include "sim/core/error.h"
#include "sim/shape/drape_import.h"

namespace vf {
namespace {

// Where each body is at one frame: all the drawing needs from a simulated state.
struct BodyPose {
  Vec3 x;
  Quat q;
  bool active;
};

std::vector<BodyPose> capturePoses(const std::vector<BodyState>& states,
                                   const std::vector<char>& active) {
  std::vector<BodyPose> poses;
  poses.reserve(states.size());
  for (std::size_t i = 0; i < states.size(); ++i)
    poses.push_back(BodyPose{states[i].x, states[i].q, active[i] != 0});
  return poses;
}

void applyPoses(const std::vector<BodyPose>& poses, std::vector<BodyView>& bodies) {
  for (std::size_t i = 0; i < poses.size(); ++i) {
    bodies[i].x = poses[i].x;
    bodies[i].q = poses[i].q;
    bodies[i].active = poses[i].active;
  }
}

double secondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

// Where the frames come from: a scene simulated here (world and recorder), or a bake.
struct ScenePlayback::Impl {
  Impl(const SceneSpec& s, int width, int height)
      : spec(s),
        built(buildScene(spec)),
        drawing(spec.camera, spec.groundPlane, width, height, spec.fps / spec.output.speed),
        bodies(bodyViews(*built->world, built->colors)),
        names(built->shapeOf) {
    recorder.emplace(*built->world, spec.fps, spec.duration);
    for (std::size_t id = 0; id < bodies.size(); ++id)
      bodies[id].smoothDegrees = smoothOf(built->shapeOf[id]);
    addTerrain(built->world->def().terrain);
  }

  Impl(std::shared_ptr<const Bake> b, int width, int height)
      : spec(b->scene),
        bake(std::move(b)),
        drawing(spec.camera, spec.groundPlane, width, height, spec.fps / spec.output.speed) {
    const auto shapes = bakeShapes(*bake);
    for (const BakeBody& body : bake->bodies) {
      BodyView v;
      v.shape = shapes[static_cast<std::size_t>(body.shape)];
      v.color = body.color;
      v.smoothDegrees = spec.shapes[static_cast<std::size_t>(body.shape)].smoothDegrees;
      bodies.push_back(v);
      names.push_back(spec.shapes[static_cast<std::size_t>(body.shape)].name);
    }
    addTerrain(loadSceneTerrain(spec));
  }

  std::optional<double> smoothOf(const std::string& shape) const {
    for (const ShapeSpec& s : spec.shapes)
      if (s.name == shape) return s.smoothDegrees;
    return std::nullopt;
  }

  // The terrain as a solid with its drape, and the light, which may need the terrain's place.
  void addTerrain(const std::shared_ptr<const Heightfield>& field) {
    drawing.setLight(sceneLight(spec.light, field.get()));
    if (!field) return;
    terrain = field;
    if (!spec.terrainTexturePath.empty())
      drape = std::make_shared<const DrapeImage>(loadDrape(spec.terrainTexturePath, *field));
    drawing.setTerrain(field, drape);
    terrainMesh = drawing.terrainSurface();
    terrainNormals = drawing.terrainSurfaceNormals();
  }

  // Drawn frames (at [output] speed) and the scene's own frames (t = j / fps), which the
  // recorder measures and which frame the shot.
  int frameCount() const {
    return Recorder::frameCountFor(spec.fps, spec.duration, spec.output.speed);
  }
  int sceneFrameCount() const { return Recorder::frameCountFor(spec.fps, spec.duration); }
  double frameTime(int k) const { return Recorder::frameTimeFor(k, spec.fps, spec.output.speed); }

  // The scene's frame j, simulating up to it (scene) or reading it (bake).
  std::vector<BodyPose> sceneFramePoses(int j) {
    if (bake) return bakePoses(Recorder::frameTimeFor(j, spec.fps));
    recorder->advanceToFrame(j);
    return capturePoses(recorder->frameStates(), recorder->frameActive());
  }
  // The poses at a time between the scene's frames, sampled between the world's own steps as
  // the recorder samples a frame (Recorder::statesAt), so the steps do not change.
  std::vector<BodyPose> posesAt(double t) {
    if (bake) return bakePoses(t);
    std::vector<char> active;
    const std::vector<BodyState> states = recorder->statesAt(t, active);
    return capturePoses(states, active);
  }
  std::vector<BodyPose> bakePoses(double t) const {
    std::vector<char> active;
    const std::vector<BodyState> states = bake->statesAt(t, active);
    return capturePoses(states, active);
  }
  // Drawn frame k's poses, kept, and its trails and chase target.
  void keepDrawnFrame(int k, std::vector<BodyPose> at) {
    poses[static_cast<std::size_t>(k)] = std::move(at);
    applyPoses(poses[static_cast<std::size_t>(k)], bodies);
    drawing.addDrawnFrame(bodies);
  }

  SceneSpec spec;
  std::optional<BuiltScene> built;   // scene: the world
  std::optional<Recorder> recorder;  // scene: its frames
  std::shared_ptr<const Bake> bake;  // bake: the recorded steps
  DrawListBuilder drawing;
  std::vector<BodyView> bodies;              // shapes and colours; poses set per frame
  std::vector<std::string> names;            // per body id: its shape's name
  std::vector<std::vector<BodyPose>> poses;  // per drawn frame
  std::shared_ptr<const Heightfield> terrain;
  std::shared_ptr<const TriMesh> terrainMesh;
  std::shared_ptr<const std::vector<Vec3>> terrainNormals;
  std::shared_ptr<const DrapeImage> drape;
};

ScenePlayback::ScenePlayback(const SceneSpec& spec, int width, int height)
    : impl_(std::make_unique<Impl>(spec, width, height)) {}

ScenePlayback::ScenePlayback(std::shared_ptr<const Bake> bake, int width, int height)
    : impl_(std::make_unique<Impl>(std::move(bake), width, height)) {}

ScenePlayback::~ScenePlayback() = default;

int ScenePlayback::frameCount() const { return impl_->frameCount(); }

const RunSummary* ScenePlayback::summary() const {
  if (impl_->bake) return impl_->bake->summary ? &*impl_->bake->summary : nullptr;
  return &impl_->recorder->summary();
}

std::uint64_t ScenePlayback::stepsSimulated() const {
  return impl_->built ? impl_->built->world->totals().steps : 0;
}

bool ScenePlayback::simulate(bool progress, const std::function<bool()>& stop) {
  Impl& p = *impl_;
  const int drawn = p.frameCount(), scene = p.sceneFrameCount();
  p.poses.assign(static_cast<std::size_t>(drawn), {});
  Progress simulating(p.spec.name + (p.bake ? " (reading the bake)" : " (simulating)"), scene,
                      progress);
  // The scene's frames j and the drawn frames k in time order. Scene frames frame the shot and
  // carry the run's diagnostics whatever the speed, so a frame drawn at one speed is the frame
  // at the same time drawn at another; a drawn frame at a scene frame's time reuses its poses.
  // At speed 1 the two sequences coincide.
  int k = 0;
  for (int j = 0; j < scene; ++j) {
    const double t = Recorder::frameTimeFor(j, p.spec.fps);
    for (; k < drawn && p.frameTime(k) < t; ++k) {
      if (stop && stop()) return false;
      p.keepDrawnFrame(k, p.posesAt(p.frameTime(k)));
    }
    if (stop && stop()) return false;
    std::vector<BodyPose> at = p.sceneFramePoses(j);
    applyPoses(at, p.bodies);
    p.drawing.include(p.bodies);
    if (k < drawn && p.frameTime(k) == t) p.keepDrawnFrame(k++, std::move(at));
    simulating.update(j + 1, t);
  }
  // Drawn frames past the last scene frame (duration * fps not a whole number).
  for (; k < drawn; ++k) {
    if (stop && stop()) return false;
    p.keepDrawnFrame(k, p.posesAt(p.frameTime(k)));
  }
  return true;
}

std::string DrawnFrames::span() const {
  return first == last ? "frame " + std::to_string(first)
                       : "frames " + std::to_string(first) + ".." + std::to_string(last);
}

DrawnFrames ScenePlayback::drawFrames(gl::Renderer& renderer, FrameSink& sink, int first, int last,
                                      bool progress, const std::function<bool()>& stop) {
  VF_ASSERT(first >= 0 && first <= last && last < frameCount());
  DrawnFrames d;
  d.first = first;
  d.last = first - 1;
  Progress drawing(impl_->spec.name + " (drawing)", last - first + 1, progress);
  const auto start = std::chrono::steady_clock::now();
  Image image;
  try {
    for (int k = first; k <= last && !(stop && stop()); ++k) {
      const auto frameStart = std::chrono::steady_clock::now();
      draw(renderer, k, image);
      d.redrawn += renderer.redrawnFraction();
      sink.write(k, image);
      d.seconds += secondsSince(frameStart);
      d.last = k;
      char detail[64];
      const double seconds = secondsSince(start);
      std::snprintf(detail, sizeof detail, "frame %d, %.2f frames/s", k,
                    seconds > 0 ? (k - first + 1) / seconds : 0.0);
      drawing.update(k - first + 1, detail);
    }
    drawing.finish();
    if (sink.framesWritten() > 0) sink.finish();
  } catch (const std::exception&) {
    if (sink.framesWritten() > 0) {
      try {
        sink.finish();
        std::fprintf(stderr, "voxfall: incomplete output: %s written to %s\n", d.span().c_str(),
                     sink.path().c_str());
      } catch (const std::exception&) {
      }
    }
    throw;
  }
  return d;
}

double ScenePlayback::frameTime(int k) const { return impl_->frameTime(k); }

DrawList ScenePlayback::drawList(int k) {
  Impl& p = *impl_;
  VF_ASSERT(k >= 0 && static_cast<std::size_t>(k) < p.poses.size());
  applyPoses(p.poses[static_cast<std::size_t>(k)], p.bodies);
  return p.drawing.build(p.bodies, k);
}

void ScenePlayback::draw(gl::Renderer& renderer, int k, Image& out,
                         const std::function<void(DrawList&)>& adjust) {
  DrawList list = drawList(k);
  if (adjust) adjust(list);
  renderer.render(list, out);
  const OutputSpec& o = impl_->spec.output;
  if (o.overlayTime || o.overlayScale)
    drawOverlays(out, OverlaySettings{o.overlayTime, o.overlayScale}, list.camera, frameTime(k),
                 o.speed);
}

std::vector<BodyView> ScenePlayback::bodiesAt(int k) {
  Impl& p = *impl_;
  VF_ASSERT(k >= 0 && static_cast<std::size_t>(k) < p.poses.size());
  applyPoses(p.poses[static_cast<std::size_t>(k)], p.bodies);
  return p.bodies;
}

std::shared_ptr<const TriMesh> ScenePlayback::terrainMesh() const { return impl_->terrainMesh; }

std::shared_ptr<const std::vector<Vec3>> ScenePlayback::terrainNormals() const {
  return impl_->terrainNormals;
}

std::shared_ptr<const Heightfield> ScenePlayback::terrain() const { return impl_->terrain; }

std::shared_ptr<const DrapeImage> ScenePlayback::terrainTexture() const { return impl_->drape; }

const std::vector<std::string>& ScenePlayback::shapeNames() const { return impl_->names; }

const OutputSpec& ScenePlayback::output() const { return impl_->spec.output; }

namespace {

// Throws InputError naming `where` unless every frame lies in 0 .. frameCount - 1.
void checkFrames(const std::string& where, const std::vector<int>& frames, int frameCount,
                 const std::string& whose) {
  for (const int k : frames) {
    if (k < 0 || k >= frameCount) {
      throw InputError(where, "frame " + std::to_string(k) + " is outside " + whose +
                                  " frames 0:" + std::to_string(frameCount - 1));
    }
  }
}

// Pass 1 over the whole playback, then `frames` drawn at width x height.
std::vector<Image> drawFrames(ScenePlayback& playback, const std::vector<int>& frames, int width,
                              int height, gl::Context& context, const std::string& shaderDir,
                              const std::function<void(DrawList&)>& adjust) {
  context.makeCurrent();
  gl::RenderSettings settings;
  settings.width = width;
  settings.height = height;
  settings.shaderDir = shaderDir;
  settings.alpha = playback.output().alpha;
  gl::Renderer renderer(context, settings);
  playback.simulate(false);
  std::vector<Image> images(frames.size());
  for (std::size_t i = 0; i < frames.size(); ++i)
    playback.draw(renderer, frames[i], images[i], adjust);
  return images;
}

}  // namespace

RenderedFrames renderSceneFrames(const SceneSpec& spec, const std::vector<int>& frames,
                                 gl::Context& context, const std::string& shaderDir,
                                 const std::function<void(DrawList&)>& adjust) {
  const int width = spec.output.width, height = spec.output.height;
  // Checked before the expensive shape building, as `render` does.
  checkFrames(spec.path, frames,
              Recorder::frameCountFor(spec.fps, spec.duration, spec.output.speed), "the scene's");
  ScenePlayback playback(spec, width, height);
  RenderedFrames out;
  out.images = drawFrames(playback, frames, width, height, context, shaderDir, adjust);
  out.summary = *playback.summary();  // a scene: always a run
  return out;
}

std::vector<Image> renderBakeFrames(std::shared_ptr<const Bake> bake, const std::string& where,
                                    const std::vector<int>& frames, int width, int height,
                                    gl::Context& context, const std::string& shaderDir) {
  checkFrames(
      where, frames,
      Recorder::frameCountFor(bake->scene.fps, bake->scene.duration, bake->scene.output.speed),
      "the bake's");
  ScenePlayback playback(std::move(bake), width, height);
  return drawFrames(playback, frames, width, height, context, shaderDir, {});
}

}  // namespace vf

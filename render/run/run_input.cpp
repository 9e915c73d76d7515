#include "render/run/run_input.h"

#include <cstdio>
#include <tuple>

#include "sim/core/error.h"

namespace vf {
namespace {

// `--fps N` and `--speed X`: the frame rate of the output and [output] speed.
void applyFrameRateOverrides(SceneSpec& spec, std::optional<double> fps,
                             std::optional<double> speed) {
  if (!fps && !speed) return;
  const double rate = fps.value_or(spec.fps), x = speed.value_or(spec.output.speed);
  const double frames = spec.duration * rate / x;
  if (frames > kMaxSceneFrames) {
    char atSpeed[64] = "";
    if (x != 1) std::snprintf(atSpeed, sizeof atSpeed, " at speed %g", x);
    char what[240];
    std::snprintf(what, sizeof what,
                  "%g frames per second%s over the scene's %g s make %g frames; at most %g are "
                  "supported",
                  rate, atSpeed, spec.duration, frames, kMaxSceneFrames);
    throw InputError(fps && speed ? "--fps and --speed" : fps ? "--fps" : "--speed", what);
  }
  spec.fps = rate;
  spec.output.speed = x;
}

void applyDrawingOverrides(RunInput& input, const std::string& path, const DrawingOverrides& d) {
  SceneSpec& spec = input.spec;
  applyFrameRateOverrides(spec, d.fps, d.speed);
  if (d.size) std::tie(spec.output.width, spec.output.height) = *d.size;
  if (d.crf) spec.output.crf = *d.crf;
  if (d.alpha) spec.output.alpha = true;
  if (d.overlay) {
    spec.output.overlayTime = d.overlay->time;
    spec.output.overlayScale = d.overlay->scale;
  }
  if (d.camera.empty()) return;
  try {
    selectCamera(spec, d.camera);
  } catch (const InputError& e) {
    // A bake carries its scene's cameras: name the file the user gave, not the scene's.
    if (!input.bake) throw;
    throw InputError(path, e.message());
  }
}

}  // namespace

RunInput loadRunInput(const std::string& path, const SceneOverrides& overrides,
                      const DrawingOverrides& drawing) {
  RunInput in;
  if (isBakeFile(path)) {
    if (overrides.any())
      throw InputError(path,
                       "--level, --step, --collider, --max-steps, --max-speed and --repair change "
                       "the run of a scene; a bake's steps are recorded (simulate the scene again "
                       "with them)");
    in.bake = readBake(path);
    in.spec = in.bake->scene;
  } else {
    in.spec = loadScene(path);
    applyOverrides(in.spec, overrides);
  }
  applyDrawingOverrides(in, path, drawing);
  return in;
}

OutputRules runOutputRules(const SceneSpec& spec, const std::string& inputFile, bool overwrite,
                           bool neverOverwrite) {
  OutputRules rules;
  rules.overwrite = neverOverwrite ? Overwrite::never
                    : overwrite    ? Overwrite::always
                                   : Overwrite::refuse;
  rules.inputs.push_back(inputFile);
  if (!spec.path.empty()) rules.inputs.push_back(spec.path);
  for (const ShapeSpec& s : spec.shapes)
    if (!s.meshPath.empty()) rules.inputs.push_back(s.meshPath);  // "" for a generated rock
  if (!spec.terrainPath.empty()) rules.inputs.push_back(spec.terrainPath);
  return rules;
}

}  // namespace vf

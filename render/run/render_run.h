// A render as a library call: what `voxfall render` does, for the command, for the commands that
// make a bake and want its video (ensemble --video-runs), and for any program or test that wants
// it without argv. A scene is simulated from t = 0 (or a bake read) and frames A..B drawn to an
// MP4 or a PNG sequence; the run summary and the drawing's numbers are printed to stdout.
//
// Order matters for the user, as in simulate: cheap checks first (input, options, output path,
// GL context and shaders), the expensive shape building and stepping last, so a typo or a
// missing GL library never costs a long run. The frames come from a ScenePlayback
// (render/scene_playback.h): the scene is simulated whole, then drawn. A render stops as
// render/run/stop_policy.h says: stopped while drawing, the frames so far stay a playable MP4 (or
// PNGs); stopped before the first frame, nothing is written.
#pragma once

#include <string>

#include "render/run/run_input.h"
#include "render/run/stop_policy.h"
#include "sim/scene/scene.h"

namespace vf {

struct RenderRequest {
  std::string input;            // scene file (TOML) or bake
  std::string output;           // "": out/<scene name>.mp4, replaced unless -n
  std::string frames;           // "A:B", "A:", ":B" or "N"; "": all
  DrawingOverrides drawing;     // fps, speed, size, crf, alpha, overlay, camera
  SceneOverrides overrides;     // level, step, collider, run limits (scenes only)
  std::string gl = "osmesa";    // osmesa or egl
  std::string shaders;          // GLSL folder ("": gl::findShaderDir's default)
  bool quiet = false;           // no progress lines, no "replacing" note
  bool overwrite = false;       // -y
  bool neverOverwrite = false;  // -n
};

// Renders as the request says. Bad input throws InputError; an error while drawing keeps the
// frames drawn (the output finalised, a note on stderr) and is rethrown.
RunStatus runRender(const RenderRequest& request);

}  // namespace vf

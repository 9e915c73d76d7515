// A filmstrip as a library call: what `voxfall filmstrip SCENE --times 0.5,1,2,4 -o FILE.png`
// does. Frames of a scene side by side with their times (the paper's figs. 20-26). Each frame is
// drawn by the same two-pass playback as render (renderSceneFrames), so the frame at t = k / fps
// is exactly the one `voxfall render --frames k:k` writes; a time between frames takes the
// nearest frame and is labelled with that frame's time. It does not poll for a stop: a signal
// removes its temporary file and ends the process (render/run/stop_policy.h).
#pragma once

#include <optional>
#include <string>
#include <utility>

#include "render/run/stop_policy.h"
#include "sim/scene/scene.h"

namespace vf {

struct FilmstripRequest {
  std::string scene;                        // scene file (TOML); not a bake
  std::string times;                        // "0.5,1,2,4": seconds
  std::string output;                       // "": out/<scene name>_filmstrip.png
  std::optional<std::pair<int, int>> size;  // each frame's width, height in pixels
  int columns = 0;                          // frames per row; 0: one row
  SceneOverrides overrides;                 // level, step, collider, run limits, repair
  bool overwrite = false;                   // -y
  bool neverOverwrite = false;              // -n
  std::string gl = "osmesa";                // osmesa or egl
  std::string shaders;                      // GLSL folder ("": gl::findShaderDir's default)
};

// Simulates, draws and writes the PNG. Bad input throws InputError.
RunStatus runFilmstrip(const FilmstripRequest& request);

}  // namespace vf

// A glTF export as a library call: what `voxfall export SCENE|BAKE -o FILE.glb` does. The
// animation as glTF 2.0 (render/export/gltf_export.h), keyframes at the frame rate, for Blender,
// three.js or any glTF viewer. A scene is simulated first, as render does; a bake is read. A
// stop before the file is written (render/run/stop_policy.h) writes nothing.
#pragma once

#include <optional>
#include <string>

#include "render/run/stop_policy.h"
#include "sim/scene/scene.h"

namespace vf {

struct ExportRequest {
  std::string input;            // scene file (TOML) or bake
  std::string output;           // "": out/<scene name>.glb
  std::optional<double> fps;    // key frames per second
  std::optional<double> speed;  // [output] speed
  SceneOverrides overrides;     // level, step, collider, run limits (scenes only)
  bool quiet = false;           // no progress line
  bool overwrite = false;       // -y
  bool neverOverwrite = false;  // -n
};

// Simulates (or reads) and writes the .glb. Bad input throws InputError.
RunStatus runExport(const ExportRequest& request);

}  // namespace vf

// What a run of the voxfall command reads: a scene file or a bake, changed by the command line's
// options, and the files it reads (which no output may replace). Shared by the commands that
// run a scene, so that all read it, and refuse to write over it, the same way.
#pragma once

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "render/output/output_file.h"
#include "sim/bake.h"
#include "sim/scene/scene.h"

namespace vf {

// What --overlay asks for: the overlays by name, each at most once ("none": no overlay).
struct OverlayChoice {
  bool time = false;
  bool scale = false;
};

// The options of `render` and `export` that change how a run is played out and drawn, never its
// steps: all that may change when the input is a bake, whose steps are recorded.
struct DrawingOverrides {
  std::optional<double> fps;                // the output's frame rate
  std::optional<double> speed;              // [output] speed
  std::optional<std::pair<int, int>> size;  // width, height in pixels
  std::optional<int> crf;                   // H.264 quality
  bool alpha = false;                       // a transparent background (PNG only)
  std::optional<OverlayChoice> overlay;     // [output] overlay
  std::string camera;                       // [cameras.NAME]; "": the scene's [camera]
};

struct RunInput {
  SceneSpec spec;            // the scene, or the bake's scene data
  std::optional<Bake> bake;  // set when the input is a bake
};

// Reads `path`, a scene file or a bake (sim/bake.h, recognised by its first line), and applies
// the overrides. `overrides` change a scene's run: for a bake they are an InputError. `drawing`
// applies to both. An InputError names the option at fault: `--fps N` and `--speed X` are checked
// as the scene's own values are (duration * fps / speed at most kMaxSceneFrames frames), and an
// unknown --camera of a bake names the bake.
RunInput loadRunInput(const std::string& path, const SceneOverrides& overrides,
                      const DrawingOverrides& drawing = {});

// The output rules of a run (-y, -n) protecting every file it reads: the scene (or bake),
// each shape's mesh, and the terrain.
OutputRules runOutputRules(const SceneSpec& spec, const std::string& inputFile, bool overwrite,
                           bool neverOverwrite);

}  // namespace vf

// voxfall export SCENE|BAKE -o FILE.glb: the animation as glTF 2.0 (render/export/
// gltf_export.h), keyframes at the frame rate, for Blender, three.js or any glTF viewer.
// A scene is simulated first, as `render` does; a bake is read.
#include <CLI/CLI.hpp>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>

#include "render/cli/commands.h"
#include "render/cli/options.h"
#include "render/cli/run_output.h"
#include "render/export/gltf_export.h"
#include "render/scene_playback.h"
#include "sim/core/error.h"
#include "sim/shape/heightfield.h"
#include "sim/shape/sphere_tree.h"

namespace vf::cli {
namespace {

struct ExportOptions {
  std::string input;
  std::string output;
  std::optional<double> fps;
  std::optional<double> speed;  // --speed X
  SceneOverrides overrides;     // --level, --step, --collider, run limits, --repair
  bool quiet = false;
  bool overwrite = false;       // -y
  bool neverOverwrite = false;  // -n
};

int runExport(const ExportOptions& o) {
  RunInput input = loadRunInput(o.input, o.overrides);
  SceneSpec& spec = input.spec;
  applyFrameRateOverrides(spec, o.fps, o.speed);
  const std::string path = o.output.empty() ? "out/" + spec.name + ".glb" : o.output;
  if (std::filesystem::path(path).extension() != ".glb")
    throw InputError(path, "the glTF export writes binary glTF: give a .glb file name");
  const OutputRules rules = runOutputRules(spec, o.input, o.overwrite, o.neverOverwrite);
  checkOutputPath(path, rules);  // before the simulation

  std::optional<ScenePlayback> played;
  if (input.bake) {
    input.bake->scene = spec;
    played.emplace(std::make_shared<const Bake>(std::move(*input.bake)), 16, 16);
  } else {
    played.emplace(spec, 16, 16);  // the size only matters for drawing
  }
  installStopHandlers();
  if (!played->simulate(!o.quiet, [] { return stopSignal() != 0; })) {
    std::fprintf(stderr, "voxfall: interrupted; nothing written\n");
    return 128 + stopSignal();
  }
  AnimationExport animation;
  animation.name = spec.name;
  animation.fps = spec.fps;
  animation.shapeNames = played->shapeNames();
  animation.terrain = played->terrainMesh();
  animation.terrainNormals = played->terrainNormals();
  animation.terrainTexture = played->terrainTexture();
  if (const auto terrain = played->terrain())
    animation.georeference = DemGeoreference{terrain->crsName, terrain->crsWkt, terrain->shift};
  for (int k = 0; k < played->frameCount(); ++k) animation.frames.push_back(played->bodiesAt(k));
  writeGltfAnimation(path, animation, rules);
  std::printf("%s: %d frames at %g fps, %zu bodies -> %s\n", spec.name.c_str(),
              played->frameCount(), spec.fps, animation.frames.front().size(), path.c_str());
  return 0;
}

}  // namespace

void addExportCommand(CLI::App& app, int& exitCode) {
  auto o = std::make_shared<ExportOptions>();
  CLI::App* sub = app.add_subcommand(
      "export",
      "Write a scene's or a bake's animation as glTF 2.0 (.glb): meshes, one animated "
      "node per body, a key per frame");
  sub->add_option("INPUT", o->input, "scene file (TOML) or bake")->required()->type_name("");
  sub->add_option("-o,--output", o->output, "FILE.glb (default: out/<scene name>.glb)")
      ->type_name("FILE");
  sub->add_option("--fps", o->fps, "key frames per second (overrides [simulation] fps)")
      ->check(finiteNumberIn(0.001, 1000.0))
      ->type_name("N");
  addSpeedOption(*sub, o->speed);
  addPhysicsOptions(*sub, o->overrides, " (scenes only)");
  addThreadsOption(*sub, o->overrides, " (scenes only)");
  sub->add_flag("--quiet,-q", o->quiet, "no progress line on stderr");
  addOverwriteFlags(*sub, o->overwrite, o->neverOverwrite);
  sub->callback([o, &exitCode] { exitCode = runExport(*o); });
}

}  // namespace vf::cli

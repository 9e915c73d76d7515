#include "render/run/export_run.h"

#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <utility>

#include "render/export/gltf_export.h"
#include "render/run/run_input.h"
#include "render/scene_playback.h"
#include "sim/core/error.h"
#include "sim/shape/heightfield.h"
#include "sim/shape/sphere_tree.h"

namespace vf {

RunStatus runExport(const ExportRequest& o) {
  DrawingOverrides rate;
  rate.fps = o.fps;
  rate.speed = o.speed;
  RunInput input = loadRunInput(o.input, o.overrides, rate);
  const SceneSpec& spec = input.spec;
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
  watchForStop();
  if (!played->simulate(!o.quiet, [] { return stopRequested() != 0; }))
    return stoppedWithNothingWritten("interrupted; nothing written");
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
  return RunStatus::done();
}

}  // namespace vf

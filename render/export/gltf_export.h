// glTF 2.0 export of an animation: `voxfall export SCENE|BAKE -o FILE.glb`,
// so Blender, three.js or any glTF viewer plays a run. Written through assimp's exporter
// (format "glb2"); only gltf_export.cpp includes assimp's headers.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "render/draw_list.h"
#include "render/output/output_file.h"

namespace vf {

// What the file holds: one mesh and one node per body (the shape's mesh in its body frame,
// with the body's colour), optionally a static terrain node, and one animation with a
// translation, rotation and scale key per body per frame (t = k / fps; scale 0 while a body is
// not yet released).
struct AnimationExport {
  std::string name;                           // scene name: the animation's and the root's
  double fps = 30;                            // frames per second
  std::vector<std::vector<BodyView>> frames;  // frame k: every body's view (same shapes)
  std::shared_ptr<const TriMesh> terrain;     // world coordinates; null: none
};

// Writes `animation` as binary glTF 2.0 to `path` (an OutputFile under `rules`). The root
// node ("world") turns voxfall's z-up world into glTF's y-up (x, y, z) -> (x, z, -y), so the
// bodies' own nodes keep voxfall's coordinates: centre of mass (m) and orientation. Throws
// InputError.
void writeGltfAnimation(const std::string& path, const AnimationExport& animation,
                        const OutputRules& rules);

}  // namespace vf

// glTF 2.0 export of an animation: `voxfall export SCENE|BAKE -o FILE.glb`,
// so Blender, three.js or any glTF viewer plays a run. Written through assimp's exporter
// (format "glb2"), with the extras assimp does not write added to the file's JSON; only
// gltf_export.cpp includes assimp's headers.
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "render/draw_list.h"
#include "render/output/output_file.h"
#include "sim/shape/drape_import.h"

namespace vf {

// Where a terrain's DEM came from, for GIS-aware importers: world = DEM coordinates + offset.
struct DemGeoreference {
  std::string crs;             // "AUTHORITY:CODE" (e.g. "EPSG:31287"); empty when the CRS has none
  std::string crsWkt;          // the DEM's CRS as WKT; empty when the file has no CRS
  Vec3 offset = Vec3::Zero();  // [ground] offset, m
};

// What the file holds: one mesh per shape and colour, shared by the nodes of every body of
// that shape and colour (the shape's mesh in its body frame, flat normals as voxfall draws
// bodies, the colour as its material: a glTF mesh carries its material); one node per body,
// named after its shape and body id ("rock_12"); optionally the static terrain (smooth normals,
// as drawn) in a node "terrain", with its draped texture embedded as a PNG and texture
// coordinates that put each world point (x, y) on the texel the renderer puts it on; and one
// animation with a translation, rotation and scale key per body per frame (scale 0 while a
// body is not yet released).
struct AnimationExport {
  std::string name;                           // scene name: the animation's
  double fps = 30;                            // key frames per second of the animation
  std::vector<std::vector<BodyView>> frames;  // frame k: every body's view (same shapes)
  std::vector<std::string> shapeNames;        // per body id: its [shapes] entry's name
  std::shared_ptr<const TriMesh> terrain;     // world coordinates; null: none
  std::shared_ptr<const std::vector<Vec3>> terrainNormals;  // per terrain vertex, unit
  std::shared_ptr<const DrapeImage> terrainTexture;         // draped on the terrain; null: none
  std::optional<DemGeoreference> georeference;              // with a terrain from a DEM
};

// A body's node name: its shape's name and its body id, "rock_12" (unique: the id follows the
// last '_').
std::string bodyNodeName(const std::string& shape, int id);

// Writes `animation` as binary glTF 2.0 to `path` (an OutputFile under `rules`). The root
// node ("world") turns voxfall's z-up world into glTF's y-up (x, y, z) -> (x, z, -y), so the
// bodies' own nodes keep voxfall's coordinates: centre of mass (m) and orientation. With a
// georeference, the root node's extras hold it: `crs`, `crs_wkt` and `dem_offset` ([x, y, z],
// m; a point p of the file's world frame lies at p - dem_offset in the CRS). Throws
// InputError.
void writeGltfAnimation(const std::string& path, const AnimationExport& animation,
                        const OutputRules& rules);

}  // namespace vf

// Scene files (TOML) -> plain spec structs -> World.
// loadScene() validates everything it reads and throws InputError with file:line:column;
// buildScene() loads meshes and builds shapes (errors name the mesh file).
#pragma once

#include <array>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "sim/core/math.h"
#include "sim/world.h"

namespace vf {

using Color = std::array<float, 3>;  // linear RGB in [0, 1]

struct ShapeSpec {
  std::string name;                // key of [shapes.NAME]
  std::string meshPath;            // resolved against the scene file's folder
  Vec3 scale = Vec3::Ones();       // uniform number or [sx, sy, sz] in the file
  double density = 0;              // kg/m^3
  std::optional<int> level;        // overrides [simulation] level for this shape
  std::optional<Color> color;
  bool repair = false;             // fill small holes, fix winding (geometry/mesh_repair.h)
  std::string where;               // "file:line:column" of the table, for later errors
};

struct BodySpec {
  std::string shape;
  Vec3 position = Vec3::Zero();         // where the mesh file's origin goes, m
  Quat orientation = Quat::Identity();  // file order w, x, y, z; normalised on load
  Vec3 velocity = Vec3::Zero();
  Vec3 angularVelocity = Vec3::Zero();
  bool isStatic = false;
  std::optional<Color> color;
  std::string where;
};

// Timed releases (examples 2, 4, 5, 6): body i of `count` is released at start + i*interval.
struct EmitterSpec {
  std::string shape;
  int count = 1;
  double start = 0;
  double interval = 0;
  std::vector<Vec3> positions;          // used in turn; one entry = same spot every time
  Quat orientation = Quat::Identity();
  Vec3 velocity = Vec3::Zero();
  Vec3 angularVelocity = Vec3::Zero();
  // Seeded variation (scene `jitter` table): each release draws from a portable PRNG.
  double positionJitter = 0;     // m, uniform in a cube of this half-size
  double directionJitter = 0;    // degrees, rotation of the horizontal velocity about z
  bool randomOrientation = false;
  std::uint64_t seed = 1;
  // If set, each release is lifted (z of `positions` ignored) so that its lowest point falls
  // this far onto whatever lies below it at release time: example 4's "dropped from 0.5 m"
  // onto a growing pile.
  std::optional<double> dropHeight;
  std::optional<Color> color;
  std::string where;
};

struct CameraSpec {
  bool given = false;  // false: the renderer frames all bodies and the ground automatically
  Vec3 position = Vec3(4, -6, 3);
  Vec3 lookAt = Vec3::Zero();
  Vec3 up = Vec3::UnitZ();
  double fovDegrees = 40;        // vertical
  std::optional<int> followBody; // body index whose centre of mass the camera looks at
};

struct OutputSpec {
  int width = 1280;
  int height = 720;
  int crf = 18;  // H.264 constant rate factor (0..51, lower is better)
};

struct SceneSpec {
  std::string path;  // the scene file as given
  std::string name;  // file stem: default output out/<name>.mp4
  // [simulation]
  double duration = 2.0;   // s
  int level = 4;           // voxel level Lv
  bool autoStep = true;    // eq. 20
  double fixedStep = 0;    // s, when !autoStep
  Vec3 gravity = Vec3(0, 0, -9.81);
  double fps = 30;
  RunLimits limits;        // max_steps, max_speed (run_guard.h)
  // [contact]
  ContactMaterial contact;
  // [ground]
  std::optional<double> groundPlane;
  std::string terrainPath;  // ESRI ASCII grid (heightfield), resolved; empty: no terrain
  std::vector<ShapeSpec> shapes;
  std::vector<BodySpec> bodies;
  std::vector<EmitterSpec> emitters;
  CameraSpec camera;
  OutputSpec output;
};

// Parses and validates a scene file. Unknown keys, wrong types, impossible values and missing
// mesh files throw InputError("file:line:column", "what is wrong; did you mean 'key'?").
SceneSpec loadScene(const std::string& path);

// A World built from a spec, with what the renderer needs to draw it.
struct BuiltScene {
  std::unique_ptr<World> world;
  std::vector<Color> colors;        // per body id: the body's, its shape's, or the palette
  std::vector<std::string> shapeOf; // per body id: shape name
};

// A distinct colour per body id for scenes that give none: a fixed palette of muted,
// well-separated hues (linear RGB) that reads well under the sun and on the grey floor.
Color defaultBodyColor(int id);

// Loads meshes (each file once), validates them, builds each shape's sphere tree once per
// (mesh, scale, level), and adds the bodies and the emitters' bodies (with release times).
BuiltScene buildScene(const SceneSpec& spec);

}  // namespace vf

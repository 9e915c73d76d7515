// Scene files (TOML) -> plain spec structs -> World.
// loadScene() validates everything it reads and throws InputError with file:line:column;
// buildScene() loads meshes and builds shapes (errors name the mesh file).
#pragma once

#include <array>
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "sim/core/math.h"
#include "sim/geometry/rock_mesh.h"
#include "sim/ground/barriers.h"
#include "sim/ground/evaluation_lines.h"
#include "sim/ground/ground_material.h"
#include "sim/ground/rock_monitor_settings.h"
#include "sim/scene/drawing_spec.h"
#include "sim/world.h"

namespace vf {

struct Forest;       // sim/ground/forest.h
class RockFall;      // sim/ground/rock_fall.h
struct RockFallDef;  // sim/ground/rock_fall.h

struct ShapeSpec {
  std::string name;             // key of [shapes.NAME]; NAME#k for variant k of a rock family
  std::string meshPath;         // resolved against the scene file's folder; "" for a rock
  std::optional<RockDef> rock;  // `rock = { ... }`: a generated rock instead of a mesh file
  // `rock.seeds = N` makes N shapes NAME#0 .. NAME#(N-1), seeds seed .. seed + N - 1, each with
  // `family` = NAME; "" for any other shape.
  std::string family;
  Vec3 scale = Vec3::Ones();  // uniform number or [sx, sy, sz] in the file
  double density = 0;         // kg/m^3; 0 when `mass` is given instead
  double mass = 0;            // kg; 0 when `density` is given
  bool yUp = false;           // `up = "y"`: the mesh file's y axis is up (rotated to z)
  std::optional<int> level;   // overrides [simulation] level for this shape
  std::optional<Color> color;
  bool repair = false;  // fill small holes, fix winding (geometry/mesh_repair.h)
  // `smooth`: crease angle in degrees for drawing. Edges between faces meeting at a smaller
  // angle are shaded smooth, sharper ones stay hard; unset: every face flat. Drawing only.
  std::optional<double> smoothDegrees;
  std::string where;  // "file:line:column" of the table, for later errors
};

struct BodySpec {
  std::string shape;
  Vec3 position = Vec3::Zero();         // where the mesh file's origin goes, m
  Quat orientation = Quat::Identity();  // file order w, x, y, z; normalised on load
  Vec3 velocity = Vec3::Zero();
  Vec3 angularVelocity = Vec3::Zero();
  bool isStatic = false;
  // If set, the body is lifted so its lowest point is this far above the surface directly
  // under it (terrain, floor, bodies at rest), as for emitters.
  std::optional<double> dropHeight;
  std::optional<Color> color;
  std::string where;
};

// Timed releases (examples 2, 4, 5, 6): body i of `count` is released at start + i*interval.
struct EmitterSpec {
  std::string shape;
  int count = 1;
  double start = 0;
  double interval = 0;
  std::vector<Vec3> positions;  // used in turn; one entry = same spot every time
  Quat orientation = Quat::Identity();
  Vec3 velocity = Vec3::Zero();
  Vec3 angularVelocity = Vec3::Zero();
  // Seeded variation (scene `jitter` table): each release draws from a portable PRNG.
  double positionJitter = 0;   // m, uniform in a cube of this half-size
  double directionJitter = 0;  // degrees, rotation of the horizontal velocity about z
  bool randomOrientation = false;
  std::uint64_t seed = 1;
  // If set, each release is lifted (z of `positions` ignored) so that its lowest point falls
  // this far onto whatever lies below it at release time: example 4's "dropped from 0.5 m"
  // onto a growing pile.
  std::optional<double> dropHeight;
  // If set, a release that would be born inside another body (their leaf spheres touching) is
  // raised until it clears it; other releases are left where they are.
  bool clearRelease = false;
  std::optional<Color> color;
  std::string where;
};

// [ground.materials.NAME]: a custom ground material. Stone law: unset values fall back to
// [contact]'s body_ground restitution and friction, and no rolling resistance. Slip law: mu_min,
// mu_max, kappa and beta are required, restitution defaults to 0, and an optional `scar`
// sub-table gives the soft-soil scar layer (all four of its keys required).
struct GroundMaterialSpec {
  std::string name;
  GroundLawKind law = GroundLawKind::kStone;  // `law = "stone" | "slip"`
  std::optional<double> restitution, friction, rollingResistance, tangentialRestitution;
  std::optional<double> muMin, muMax, kappa, beta;  // slip law
  // Slip law's scar layer (`scar = { density, fluid_drag, compaction_drag, modulus }`).
  struct Scar {
    double density = 0, fluidDrag = 0, compactionDrag = 0, modulus = 0;  // kg/m^3, -, -, MN/m^2
  };
  std::optional<Scar> scar;
  std::string where;
};

// [ensemble]: what varies between the realisations of `voxfall ensemble` (README, "Ensembles
// and hazard maps"). Each realisation is one rock in its own world; the scene's [[bodies]] and
// [[emitters]] are not part of it (they serve `simulate` and `render` of the same file).
//
// One release source of [ensemble.release] (a table, or an array of tables for several).
// Coordinates are the DEM's own (its CRS, before [ground] offset), as a GIS shows them.
enum class ReleaseKind { kArea, kLine, kPoints, kCells, kFile };
using Point2 = std::array<double, 2>;  // x, y (m)

// A rock-volume distribution ([ensemble] volume, or a source's own): each realisation's rock is
// its drawn shape scaled to a volume drawn from it, between `min` and `max` (m^3).
struct VolumeSpec {
  enum class Law { kLogNormal, kPower };
  Law law = Law::kLogNormal;
  double median = 0, sigma = 0;  // log-normal: median volume (m^3) and sigma of ln V
  double exponent = 0;           // power: b of the cumulative count N(> V) ~ V^-b
  double min = 0, max = 0;       // m^3, 0 < min < max
  std::string where;             // "file:line:column" of the table
};

struct ReleaseSpec {
  ReleaseKind kind = ReleaseKind::kPoints;
  std::vector<Point2> points;           // area polygon, line vertices or points, DEM x, y
  std::vector<std::string> pointWhere;  // "file:line:column" of each point
  // cells: a source raster on the DEM's grid (non-zero = source); file: a vector file (OGR).
  std::string path;
  std::string layer;        // file: the layer, empty for the first
  std::string weightField;  // file: a numeric attribute weighting each feature; empty: by size
  double weight = 1;        // this source's share of the realisations, relative to the others'
  std::string key;          // "release.area", "release[1].file", ... for messages
  std::string where;        // "file:line:column" of the form's key
  std::optional<VolumeSpec> volume;  // this source's rock volumes; none: [ensemble]'s
};

// [forest]: a stand on the DEM's grid (sim/ground/forest.h). Each quantity is a raster (any
// GDAL reads, resampled onto the DEM's grid) or one number for the whole DEM.
struct ForestSpec {
  std::string where;                   // file:line:column of the table
  std::string densityPath;             // `density` raster, stems/ha; empty: densityValue
  double densityValue = 0;             // `density` as a number, stems/ha
  std::string dbhPath;                 // `dbh` raster, cm; empty: dbhValue
  double dbhValue = 0;                 // `dbh` as a number, cm
  std::string treesPath;               // `trees` point file, instead of density and dbh
  std::string treesDbhField = "dbh";   // `trees_dbh_field`: its DBH field, cm
  std::string speciesPath;             // `species` class raster; empty: every stem class 0
  std::vector<double> speciesFactors;  // `species_factors`, per class; empty: [1]
  std::optional<double> stemHeight;    // `stem_height`, m
  std::uint64_t seed = 1;              // `seed` (an ensemble draws its own per realisation)
};

struct EnsembleSpec {
  std::uint64_t seed = 1;  // `seed`; --seed overrides it
  // `shapes` (or `shape`), drawn with `weights`; a rock family's entry is replaced by its
  // variants (NAME#k), which share the entry's weight equally.
  std::vector<std::string> shapes;
  std::vector<double> weights;        // one per entry of `shapes`, > 0; equal when not given
  std::vector<ReleaseSpec> releases;  // at least one
  std::optional<VolumeSpec> volume;   // rock volumes; none: the shapes' own sizes
  std::optional<std::array<double, 2>> density;  // kg/m^3, [lo, hi]; none: the shapes' own
  double dropHeight = 1.0;        // m, lowest point above the surface under the rock at release
  bool randomOrientation = true;  // `orientation = "random" | "fixed"` (fixed: identity)
  Vec3 velocityMin = Vec3::Zero(), velocityMax = Vec3::Zero();                // m/s, per component
  Vec3 angularVelocityMin = Vec3::Zero(), angularVelocityMax = Vec3::Zero();  // rad/s
  // Ground contact parameters drawn per realisation, [lo, hi]; unset: the scene's.
  std::optional<std::array<double, 2>> restitution, friction, rollingResistance;
  // `height_classes`: the limits (m, ascending, > 0) of the passing-height classes map
  // height_classes.png; empty: no such map.
  std::vector<double> heightClasses;
  std::string where;  // "file:line:column" of [ensemble]
};

// [[evaluation_lines]] (docs/rockfall.md, "Evaluation lines"): a polyline whose vertical curtain
// records every rock crossing it. Written in the DEM file's coordinates (its CRS, before
// [ground] offset) in the scene (`points`), or read from a vector file (`file`, each line feature
// one evaluation line) into the DEM's CRS when the scene is built.
struct EvaluationLineSpec {
  std::string name;
  std::vector<Point2> points;           // DEM file coordinates x, y, m; empty with `file`
  std::vector<std::string> pointWhere;  // "file:line:column" of each point
  std::string file;                     // vector file (OGR), resolved; empty: `points`
  std::string layer;                    // the file's layer; empty: its first
  std::string where;                    // "file:line:column" of the line's table
};

// [[barriers]] (docs/rockfall.md, "Barriers"): a rockfall net or wall along a polyline, given as
// an evaluation line is (`line`: name, points or file, where), with its height and capacity.
struct BarrierSpec {
  EvaluationLineSpec line;
  double height = 0;       // m above the ground
  double capacity = 0;     // kJ
  double thickness = 0.3;  // m
  // With `file`: numeric attributes that give each feature its own height (m) and capacity
  // (kJ) in place of `height` and `capacity`; empty: the table's value for every feature.
  std::string heightField, capacityField;
};

struct OutputSpec {
  int width = 1280;
  int height = 720;
  int crf = 18;  // H.264 constant rate factor (0..51, lower is better)
  // Simulated seconds per second of video: frame k shows t = k speed / fps (< 1 slow motion,
  // > 1 time-lapse). Drawing only: the simulation and `simulate`'s frames do not change.
  double speed = 1;
  bool alpha = false;         // PNG frames with a transparent background (no MP4)
  bool overlayTime = false;   // the simulated time (and the speed) drawn on the frame
  bool overlayScale = false;  // a scale bar drawn on the frame
};

// How bodies find their contacts: the paper's voxel sphere trees, or the polygon method it
// compares them with (convex meshes only; digest section 7).
enum class ColliderMethod { kVoxel, kPolygon };

struct SceneSpec {
  std::string path;  // the scene file as given
  std::string name;  // file stem: default output out/<name>.mp4
  // [simulation]
  double duration = 2.0;  // s
  int level = 4;          // voxel level Lv
  StepRule step;          // `step = "auto" | "clearance" | seconds`
  Vec3 gravity = Vec3(0, 0, -9.81);
  double fps = 30;
  ColliderMethod collider = ColliderMethod::kVoxel;  // collider = "voxel" | "polygon"
  // The two extensions beyond the paper that change trajectories for speed (docs/performance.md).
  // `method = "fast"` (the default: both on) or `"paper"` (both off) sets them; the keys
  // `contact_reduction` and `sleep` override it one by one. WorldDef, for code that builds a
  // World itself, keeps the paper's method as its default.
  bool contactReduction = true;  // a few contacts per patch
  bool sleep = true;             // bodies at rest sleep until touched
  int threads = 1;               // not a scene key (results do not depend on it): set by the caller
  bool stageTimes = false;       // not a scene key: time each stage of every step (WorldDef)
  RotationUpdate rotation = RotationUpdate::kExplicitEuler;  // `rotation = "euler" | "midpoint"`
  bool stopWhenSettled = false;  // `stop = "all_at_rest"`: end when every rock stopped or left
  RestCriterion rest;            // `rest = { speed = .., time = .. }`
  TerrainEdge terrainEdge = TerrainEdge::kAuto;  // [ground] edge
  RunLimits limits;                              // max_steps, max_speed (run_guard.h)
  // [contact]
  ContactMaterial contact;
  // [ground]
  std::optional<double> groundPlane;
  std::string terrainPath;           // DEM (any raster GDAL reads), resolved; empty: no terrain
  Vec3 terrainShift = Vec3::Zero();  // `offset`: added to the DEM's coordinates, m
  std::string terrainTexturePath;    // `texture`: an RGB raster draped on the DEM; empty: none
  std::string terrainCrs;  // `crs`: the DEM's CRS where its file names none; empty: the file's
  // Rock fall ground materials (opt-in). Empty `groundMaterial`: the paper's model.
  std::string groundMaterial;  // a preset (sim/ground/ground_material.cpp) or custom name
  std::vector<GroundMaterialSpec> groundMaterials;  // custom ones
  std::string groundClassesPath;  // class raster on the DEM's grid; empty: one material
  std::vector<std::pair<int, std::string>> classMaterials;  // class -> material name
  double groundVariability = 0;             // per-cell +- bound (ground_variability.h); 0: off
  std::uint64_t groundVariabilitySeed = 1;  // `variability_seed` (an ensemble draws its own)
  std::optional<ForestSpec> forest;         // [forest]; none: no trees
  std::vector<ShapeSpec> shapes;
  std::vector<BodySpec> bodies;
  std::vector<EmitterSpec> emitters;
  CameraSpec camera;                // [camera], or the one `render --camera NAME` chose
  std::vector<CameraSpec> cameras;  // [cameras.NAME] tables, in file order
  LightSpec light;                  // [light]
  OutputSpec output;
  std::optional<EnsembleSpec> ensemble;             // [ensemble]
  std::vector<EvaluationLineSpec> evaluationLines;  // [[evaluation_lines]]
  std::vector<BarrierSpec> barriers;                // [[barriers]]
};

// Parses and validates a scene file. Unknown keys, wrong types, impossible values and missing
// mesh files throw InputError("file:line:column", "what is wrong; did you mean 'key'?").
SceneSpec loadScene(const std::string& path);

// The most frames a scene may have (duration * fps): frame arrays are allocated whole. A
// scene's [simulation] and a bake's header are checked against it.
inline constexpr double kMaxSceneFrames = 1e7;

// Frame sizes in pixels per side: one limit for [output], --size, suite sizes and the renderer.
inline constexpr int kMaxImageSide = 16384;

// The one size rule of a frame side: "" when `pixels` is 1..kMaxImageSide, else the message,
// naming the side as `side` ("width" or "height"). The scene's [output], --size, suite sizes
// and the renderer all check with it. Evenness is not part of it: only an MP4 needs even sides,
// and the MP4 encoder (render/output/video_encoder.cpp) checks that once, whichever of [output]
// or --size gave the size; a PNG may be odd.
std::string frameSideProblem(const std::string& side, std::int64_t pixels);

// Overrides (the --level and --step options), shared so that `simulate` and `render` given the
// same options build the same world and report the same checksum.
// Every shape uses voxel level `level` (per-shape levels in the scene are overridden too).
void applyLevelOverride(SceneSpec& spec, int level);
// A step rule written as text, as `--step` and the scene's `step` key take it: "auto" (eq. 20),
// "clearance", or a fixed step in seconds > 0 ("0.005", or "1/120" as the paper writes steps);
// nothing for anything else.
std::optional<StepRule> parseStepRule(const std::string& text);
// What parseStepRule accepts, in words, for the messages of both (the option's and the key's).
std::string stepRuleChoices();
// "" when parseStepRule accepts `text`, else what is wrong with it.
std::string checkStepOption(const std::string& text);
// Applies a step that passed checkStepOption; throws InputError otherwise.
void applyStepOverride(SceneSpec& spec, const std::string& text);
// The contact method of every body: "voxel" (sphere trees) or "polygon" (the paper's
// comparison method, convex meshes only); throws InputError for anything else.
void applyColliderOverride(SceneSpec& spec, const std::string& method);
// Everything the command line may change in a loaded scene (--level, --step, --collider,
// --max-steps, --max-speed, --repair), applied in one place so that every command given the
// same options builds the same world and reports the same checksum.
struct SceneOverrides {
  std::optional<int> level;
  std::string step;      // "" keeps the scene's
  std::string collider;  // "" keeps the scene's
  std::optional<std::uint64_t> maxSteps;
  std::optional<double> maxSpeed;  // m/s
  bool repair = false;             // repair = true on every shape
  // Threads for the narrow phase and the solver (SceneSpec::threads). Not a change of the run
  // (the results are the same bits for any count), so any() leaves it out.
  std::optional<int> threads;
  bool any() const {
    return level || !step.empty() || !collider.empty() || maxSteps || maxSpeed || repair;
  }
};
// Applies the given overrides; throws InputError for a malformed step or collider.
void applyOverrides(SceneSpec& spec, const SceneOverrides& o);
// Makes [cameras.NAME] (or "camera", the [camera] table) the scene's camera. Throws
// InputError naming the scene's cameras when there is none by that name.
void selectCamera(SceneSpec& spec, const std::string& name);

// The scene's terrain (its DEM moved by [ground] offset), or null without one; shared by
// buildScene and the renderer of a bake.
std::shared_ptr<const Heightfield> loadSceneTerrain(const SceneSpec& spec);
// The scene's stand ([forest]) on `terrain`'s grid, or null without one. Throws InputError naming
// the raster for a raster GDAL cannot read or place (dem_grid_raster.h) and for a negative
// density or DBH, a class without a factor, or stems without a DBH.
std::shared_ptr<const Forest> buildSceneForest(const SceneSpec& spec,
                                               std::shared_ptr<const Heightfield> terrain);

// The scene's evaluation lines in world coordinates on its terrain `dem` (file coordinates
// plus dem.shift). Throws InputError naming the line and point when a vertex lies off the DEM
// or over NODATA.
std::vector<EvaluationLine> sceneEvaluationLines(const SceneSpec& spec, const Heightfield& dem);
// The scene's barriers in world coordinates on `dem` (capacity in J), checked as the lines are.
std::vector<Barrier> sceneBarriers(const SceneSpec& spec, const Heightfield& dem);
// Adds the barriers' static pieces (`pieces[b]`: barrierPieces of barrier b) to `world` and
// makes their capacity rule act after every step (World::addStepListener); the returned monitor
// holds their results.
std::shared_ptr<const BarrierMonitor> attachBarriers(
    World& world, const std::vector<Barrier>& barriers,
    const std::vector<std::vector<BarrierPiece>>& pieces);

// A World built from a spec, with what the renderer needs to draw it.
struct BuiltScene {
  std::unique_ptr<World> world;
  // Rock fall, attached to `world` (sim/ground/rock_fall_world.h): its outcomes, stop reason,
  // terrain messages, tree hits, slippage and scar depth. Never null; idle without a ground
  // map, forest or terrain.
  RockFall* rockFall = nullptr;
  std::vector<EvaluationLine> evaluationLines;     // world coordinates (sceneEvaluationLines)
  std::shared_ptr<const BarrierMonitor> barriers;  // null without [[barriers]]
  std::vector<Color> colors;         // per body id: the body's, its shape's, or the palette
  std::vector<std::string> shapeOf;  // per body id: shape name
};

// A distinct colour per body id for scenes that give none: a fixed palette of muted,
// well-separated hues (linear RGB) that reads well under the sun and on the grey floor.
Color defaultBodyColor(int id);

// The World settings of a scene (terrain loaded), without bodies.
WorldDef sceneWorldDef(const SceneSpec& spec);
// The scene's rock-fall settings on `terrain` (its DEM, or null): the ground map, the stand, the
// edge policy and the rest criterion.
RockFallDef sceneRockFallDef(const SceneSpec& spec, std::shared_ptr<const Heightfield> terrain);
// Each shape of a scene built once (mesh read once per file, sphere tree once per mesh, scale
// and level), by name, with the shape's colour if it has one.
struct SceneShape {
  std::shared_ptr<const Shape> shape;
  std::optional<Color> color;
};
std::map<std::string, SceneShape> buildSceneShapes(const SceneSpec& spec);
// A shape's mesh before `scale`: its rock generated, or its mesh file imported, repaired when
// asked, checked closed (InputError naming the file) and turned z-up. Bakes rebuild their
// shapes' meshes with it too.
TriMesh shapeSourceMesh(const ShapeSpec& s);
// The shape's scale in the axes of shapeSourceMesh (a y-up mesh's y and z factors swap).
Vec3 shapeScale(const ShapeSpec& s);
// Equal for two shapes exactly when shapeSourceMesh gives them the same mesh (file, up axis and
// repair, or the whole rock definition): the key of the caches of meshes and sphere trees.
std::string shapeMeshKey(const ShapeSpec& s);
// Centre of mass of a body of `shape` whose mesh-file origin is at `filePosition` with
// orientation q (scenes place the file origin; the World places the centre of mass), m.
Vec3 centreOfMass(const Shape& shape, const Vec3& filePosition, const Quat& q);
// A rotation drawn uniformly from SO(3) (Shoemake, Graphics Gems III) from three uniforms in
// [0, 1).
Quat uniformRotation(double u1, double u2, double u3);

// Loads meshes (each file once) or generates rocks, validates them, builds each shape's sphere
// tree once per (mesh, scale, level), and adds the bodies and the emitters' bodies (with release
// times).
BuiltScene buildScene(const SceneSpec& spec);

}  // namespace vf

// SceneSpec -> World. Meshes are imported (or rocks generated) once each and sphere trees built
// once per (mesh, scale, level), the expensive parts; shapes are then cheap views sharing them.
// Body ids follow the spec: [[bodies]] in file order, then each emitter's releases in turn
// (camera `follow` indices rely on this order).
#include <cmath>
#include <cstdio>
#include <map>
#include <memory>
#include <numbers>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "sim/core/error.h"
#include "sim/core/prng.h"
#include "sim/geometry/mass_properties.h"
#include "sim/geometry/mesh_checks.h"
#include "sim/geometry/mesh_import.h"
#include "sim/geometry/mesh_repair.h"
#include "sim/geometry/rock_mesh.h"
#include "sim/ground/ground_material.h"
#include "sim/ground/rock_fall_world.h"
#include "sim/run_length.h"
#include "sim/scene/scene.h"
#include "sim/shape/convex_polyhedron.h"
#include "sim/shape/crs.h"
#include "sim/shape/shape.h"
#include "sim/shape/sphere_tree.h"

namespace vf {
namespace {

using BuiltShape = SceneShape;

// Sphere trees are a pure function of the scaled, centred mesh and the level, so
// shapes that differ only in density or colour share one.
using TreeKey = std::tuple<std::string, double, double, double, int>;

}  // namespace

std::string shapeMeshKey(const ShapeSpec& s) {
  if (s.rock) {
    // Hexadecimal floats: two rocks share a mesh only when their sizes are the same bits.
    char buf[256];
    std::snprintf(buf, sizeof buf, "\n(rock) %s seed %llu size %a %a %a length %a volume %a",
                  s.rock->shapeClass.c_str(), static_cast<unsigned long long>(s.rock->seed),
                  s.rock->extents.x(), s.rock->extents.y(), s.rock->extents.z(), s.rock->length,
                  s.rock->volume);
    return buf;
  }
  return s.meshPath + (s.yUp ? "#y-up" : "") + (s.repair ? "\n(repaired)" : "");
}

TriMesh shapeSourceMesh(const ShapeSpec& s) {
  if (s.rock) return makeRockMesh(*s.rock);  // closed, convex and outward by construction
  // Both throw InputError naming the mesh file.
  TriMesh m = importMesh(s.meshPath);
  if (s.repair) {
    RepairReport report;
    m = repairMesh(m, s.meshPath, report);
    // What repair changed is the user's to know (and to fix in the file for good).
    std::fprintf(stderr, "voxfall: %s: repaired: %s\n", s.meshPath.c_str(),
                 report.summary().c_str());
    validateClosedMesh(m, s.meshPath);
  } else {
    try {
      validateClosedMesh(m, s.meshPath);
    } catch (const InputError& e) {
      // Only the faults repair can fix get the hint.
      const std::string& text = e.message();
      if (text.find("not closed") == std::string::npos &&
          text.find("inconsistently oriented") == std::string::npos &&
          text.find("degenerate") == std::string::npos &&
          text.find("not manifold") == std::string::npos)
        throw;
      throw InputError(e.where(), e.message() + " (or set repair = true on [shapes." + s.name +
                                      "], or pass --repair, to fill small holes and fix "
                                      "duplicate, degenerate and flipped triangles)");
    }
  }
  // +90 degrees about x takes the file's y (up) to z and its z to -y: a proper rotation,
  // so windings (outward normals) are kept.
  if (s.yUp)
    for (Vec3& v : m.vertices) v = Vec3(v.x(), -v.z(), v.y());
  return m;
}

Vec3 shapeScale(const ShapeSpec& s) {
  // `scale` is given in the mesh file's axes: after the y-up rotation its y and z swap.
  return s.yUp ? Vec3(s.scale.x(), s.scale.z(), s.scale.y()) : s.scale;
}

std::map<std::string, SceneShape> buildSceneShapes(const SceneSpec& spec) {
  std::map<std::string, TriMesh> meshes;  // by shapeMeshKey
  std::map<TreeKey, std::shared_ptr<const SphereTree>> trees;
  std::map<std::string, BuiltShape> shapes;
  for (std::size_t i = 0; i < spec.shapes.size(); ++i) {
    const ShapeSpec& s = spec.shapes[i];
    // A y-up mesh is a different mesh once rotated, a repaired mesh another mesh than the
    // file's, and each rock its own: each gets its own cache entry and tree.
    const std::string meshKey = shapeMeshKey(s);
    auto mesh = meshes.find(meshKey);
    if (mesh == meshes.end()) mesh = meshes.emplace(meshKey, shapeSourceMesh(s)).first;
    const int level = s.level.value_or(spec.level);
    const Vec3 scale = shapeScale(s);
    const TreeKey key{meshKey, scale.x(), scale.y(), scale.z(), level};
    auto tree = trees.find(key);
    if (tree == trees.end()) {
      auto built = std::make_shared<const SphereTree>(
          buildSphereTree(centredMesh(mesh->second, scale), level));
      tree = trees.emplace(key, std::move(built)).first;
    }
    // `mass` instead of `density`: the uniform density that gives the scaled mesh that mass.
    const double density =
        s.mass > 0 ? s.mass / computeMassProperties(centredMesh(mesh->second, scale), 1.0).volume
                   : s.density;
    BuiltShape b;
    b.shape = makeShape(s.name, mesh->second, scale, density, level, tree->second);
    if (spec.collider == ColliderMethod::kPolygon) {
      // Throws InputError at the shape's table when the mesh is not convex.
      auto withPolygons = std::make_shared<Shape>(*b.shape);
      withPolygons->polyhedron = std::make_shared<const ConvexPolyhedron>(
          buildConvexPolyhedron(withPolygons->mesh, s.name, s.where));
      b.shape = std::move(withPolygons);
    }
    b.color = s.color;
    shapes.emplace(s.name, std::move(b));
  }
  return shapes;
}

namespace {

const BuiltShape& findShape(const std::map<std::string, BuiltShape>& shapes,
                            const std::string& name, const std::string& where) {
  auto it = shapes.find(name);
  // loadScene already rejects this; a spec built in code may not have been through it.
  if (it == shapes.end()) throw InputError(where, "unknown shape '" + name + "'");
  return it->second;
}

// The ground material named `name`: a custom one (a stone material's unset values from
// [contact]; a slip material's restitution 0, Leine et al. 2014's eps_N), else a preset with
// [contact]'s body_ground friction.
GroundMaterial groundMaterial(const SceneSpec& spec, const std::string& name) {
  for (const GroundMaterialSpec& g : spec.groundMaterials)
    if (g.name == name) {
      GroundMaterial m;
      m.name = name;
      m.law = g.law;
      const bool slip = g.law == GroundLawKind::kSlip;
      m.restitution = g.restitution.value_or(slip ? 0.0 : spec.contact.restitutionBodyGround);
      m.friction = g.friction.value_or(spec.contact.frictionBodyGround);
      m.rollingResistance = g.rollingResistance.value_or(0.0);
      m.tangentialRestitution = g.tangentialRestitution.value_or(1.0);
      m.muMin = g.muMin.value_or(0.0);
      m.muMax = g.muMax.value_or(0.0);
      m.kappa = g.kappa.value_or(0.0);
      m.beta = g.beta.value_or(0.0);
      if (g.scar) {
        m.scar = true;
        m.scarDensity = g.scar->density;
        m.scarFluidDrag = g.scar->fluidDrag;
        m.scarCompactionDrag = g.scar->compactionDrag;
        m.scarModulus = g.scar->modulus;
      }
      m.source = "scene " + g.where;
      return m;
    }
  if (auto p = groundPreset(name, spec.contact.frictionBodyGround)) return *p;
  throw InputError(spec.path, "unknown ground material '" + name + "'");  // loadScene checks
}

std::shared_ptr<const GroundMap> buildGroundMap(const SceneSpec& spec,
                                                std::shared_ptr<const Heightfield> terrain) {
  const Heightfield* dem = terrain.get();
  auto map = std::make_shared<GroundMap>();
  map->materials.push_back(groundMaterial(spec, spec.groundMaterial));
  if (spec.groundVariability > 0) {
    map->variability = spec.groundVariability;
    map->variabilitySeed = spec.groundVariabilitySeed;
    map->cells = terrain;
  }
  if (spec.groundClassesPath.empty()) return map;
  Heightfield classes = loadDem(spec.groundClassesPath);
  shiftHeightfield(classes, Vec3(spec.terrainShift.x(), spec.terrainShift.y(), 0));
  if (!dem || classes.nx != dem->nx || classes.ny != dem->ny ||
      std::abs(classes.x0 - dem->x0) > 1e-6 * dem->cell ||
      std::abs(classes.y0 - dem->y0) > 1e-6 * dem->cell ||
      std::abs(classes.cell - dem->cell) > 1e-9 * dem->cell)
    throw InputError(
        spec.groundClassesPath,
        "class raster must lie on the DEM's grid (" + std::to_string(dem ? dem->nx : 0) + " x " +
            std::to_string(dem ? dem->ny : 0) + " samples, same origin and cell size), got " +
            std::to_string(classes.nx) + " x " + std::to_string(classes.ny));
  for (const auto& [cls, name] : spec.classMaterials) {
    if (static_cast<std::size_t>(cls) >= map->materialOfClass.size())
      map->materialOfClass.resize(static_cast<std::size_t>(cls) + 1, -1);
    map->materialOfClass[static_cast<std::size_t>(cls)] = static_cast<int>(map->materials.size());
    map->materials.push_back(groundMaterial(spec, name));
  }
  map->classes = std::make_shared<const Heightfield>(std::move(classes));
  return map;
}

}  // namespace

// The World places bodies by their centre of mass; scenes place the mesh file's origin. The
// body frame has the centre of mass at its origin and the file origin at shape.meshOrigin, so
// position = x + R * meshOrigin, i.e. x = position - R * meshOrigin.
Vec3 centreOfMass(const Shape& shape, const Vec3& filePosition, const Quat& q) {
  return filePosition - q.toRotationMatrix() * shape.meshOrigin;
}

Quat uniformRotation(double u1, double u2, double u3) {
  const double twoPi = 2 * std::numbers::pi;
  const double a = std::sqrt(1 - u1), b = std::sqrt(u1);
  return Quat(b * std::cos(twoPi * u3), a * std::sin(twoPi * u2), a * std::cos(twoPi * u2),
              b * std::sin(twoPi * u3));
}

Color defaultBodyColor(int id) {
  // Hand-picked: hue steps far apart in order, similar lightness, saturation kept below
  // "toy" levels so shading stays readable. Linear RGB (sRGB values in the comments).
  static constexpr std::array<Color, 10> kPalette{{
      {0.578f, 0.091f, 0.047f},  // brick red      #C8553D
      {0.048f, 0.202f, 0.440f},  // steel blue     #3E7CB1
      {0.745f, 0.352f, 0.030f},  // ochre          #E0A030
      {0.105f, 0.323f, 0.084f},  // moss green     #5B9A52
      {0.270f, 0.112f, 0.361f},  // plum           #8E5EA2
      {0.027f, 0.332f, 0.323f},  // teal           #2E9C9A
      {0.658f, 0.162f, 0.262f},  // rose           #D4708C
      {0.332f, 0.296f, 0.238f},  // warm grey      #9C9486
      {0.807f, 0.216f, 0.042f},  // orange         #E8803A
      {0.156f, 0.195f, 0.332f},  // slate          #6E7A9C
  }};
  return kPalette[static_cast<std::size_t>(id < 0 ? -id : id) % kPalette.size()];
}

std::shared_ptr<const Heightfield> loadSceneTerrain(const SceneSpec& spec) {
  if (spec.terrainPath.empty()) return nullptr;
  Heightfield terrain = loadDem(spec.terrainPath);
  if (!spec.terrainCrs.empty()) assignCrs(terrain, parseCrs(spec.terrainCrs), spec.terrainPath);
  if (spec.terrainShift != Vec3::Zero()) shiftHeightfield(terrain, spec.terrainShift);
  return std::make_shared<const Heightfield>(std::move(terrain));
}

WorldDef sceneWorldDef(const SceneSpec& spec) {
  WorldDef def;
  def.gravity = spec.gravity;
  def.step = spec.step;
  def.groundHeight = spec.groundPlane;
  def.terrain = loadSceneTerrain(spec);
  def.rotation = spec.rotation;
  def.contact = spec.contact;
  def.contactReduction = spec.contactReduction;
  def.sleep = spec.sleep;
  def.threads = spec.threads;
  def.stageTimes = spec.stageTimes;
  def.limits = spec.limits;
  return def;
}

RockFallDef sceneRockFallDef(const SceneSpec& spec, std::shared_ptr<const Heightfield> terrain) {
  RockFallDef def;
  if (!spec.groundMaterial.empty()) def.ground = buildGroundMap(spec, terrain);
  def.forest = buildSceneForest(spec, terrain);
  if (spec.forest) def.forestSeed = spec.forest->seed;
  def.terrainEdge = spec.terrainEdge;
  def.rest = spec.rest;
  return def;
}

namespace {

// Adds bodies to a scene's world in id order, with their colour, shape name and where the
// scene gives them (for the run-length check).
struct BodyAdder {
  BuiltScene& out;
  std::vector<std::string> where;  // per body id

  void add(const BuiltShape& s, const std::string& shapeName, BodyDef body,
           const std::optional<Color>& color, const std::string& at) {
    where.push_back(at);
    body.shape = s.shape;
    const int id = out.world->addBody(body);
    VF_ASSERT(id == static_cast<int>(out.colors.size()));
    out.colors.push_back(color.value_or(s.color.value_or(defaultBodyColor(id))));
    out.shapeOf.push_back(shapeName);
  }
};

// The scene's [[bodies]], in file order.
void addSceneBodies(const SceneSpec& spec, const std::map<std::string, BuiltShape>& shapes,
                    BodyAdder& bodies) {
  for (const BodySpec& b : spec.bodies) {
    const BuiltShape& s = findShape(shapes, b.shape, b.where);
    BodyDef def;
    def.orientation = b.orientation.normalized();
    def.position = centreOfMass(*s.shape, b.position, def.orientation);
    def.velocity = b.velocity;
    def.angularVelocity = b.angularVelocity;
    def.isStatic = b.isStatic;
    if (b.dropHeight) def.dropHeight = *b.dropHeight;
    bodies.add(s, b.shape, def, b.color, b.where);
  }
}

// Release i of emitter e. Each release draws the same seven numbers from rng whichever jitter
// is switched on: changing one kind of jitter does not reshuffle the others.
BodyDef emitterRelease(const EmitterSpec& e, const Shape& shape, int i, Prng& rng) {
  const Vec3 offset(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1));
  const double turn = rng.uniform(-1, 1);
  const double u1 = rng.uniform(), u2 = rng.uniform(), u3 = rng.uniform();

  Vec3 position = e.positions[static_cast<std::size_t>(i) % e.positions.size()];
  Vec3 velocity = e.velocity;
  Quat orientation = e.orientation.normalized();
  if (e.positionJitter > 0) position += e.positionJitter * offset;
  if (e.directionJitter > 0) {
    // Rotating about z turns the horizontal part and keeps the vertical one.
    const double angle = e.directionJitter * turn * std::numbers::pi / 180;
    velocity = Eigen::AngleAxisd(angle, Vec3::UnitZ()) * velocity;
  }
  if (e.randomOrientation) orientation = (uniformRotation(u1, u2, u3) * orientation).normalized();

  BodyDef def;
  def.orientation = orientation;
  def.position = centreOfMass(shape, position, orientation);
  def.velocity = velocity;
  def.angularVelocity = e.angularVelocity;
  def.releaseTime = e.start + i * e.interval;
  if (e.dropHeight) def.dropHeight = *e.dropHeight;
  def.clearRelease = e.clearRelease;
  return def;
}

// Each emitter's releases in turn. One generator per emitter, seeded from the scene, so that
// adding an emitter does not change its neighbours.
void addEmitterReleases(const SceneSpec& spec, const std::map<std::string, BuiltShape>& shapes,
                        BodyAdder& bodies) {
  for (const EmitterSpec& e : spec.emitters) {
    const BuiltShape& s = findShape(shapes, e.shape, e.where);
    if (e.positions.empty()) throw InputError(e.where, "emitter has no position");
    Prng rng(e.seed);
    for (int i = 0; i < e.count; ++i)
      bodies.add(s, e.shape, emitterRelease(e, *s.shape, i, rng), e.color, e.where);
  }
}

// The barriers on the terrain, after every rock, so body ids of bodies and emitters stay as the
// scene numbers them.
void addSceneBarriers(const SceneSpec& spec, BodyAdder& bodies) {
  BuiltScene& out = bodies.out;
  if (!out.world->def().terrain || spec.barriers.empty()) return;
  const std::vector<Barrier> barriers = sceneBarriers(spec, *out.world->def().terrain);
  std::vector<std::vector<BarrierPiece>> pieces;
  for (const Barrier& b : barriers)
    pieces.push_back(barrierPieces(b, *out.world->def().terrain, spec.level));
  const int first = out.world->bodyCount();
  out.barriers = attachBarriers(*out.world, barriers, pieces);
  for (int id = first; id < out.world->bodyCount(); ++id) {
    out.colors.push_back(Color{0.25f, 0.25f, 0.27f});
    out.shapeOf.push_back(out.world->shape(id).name);
    bodies.where.push_back(spec.path);
  }
}

}  // namespace

BuiltScene buildScene(const SceneSpec& spec) {
  BuiltScene out;
  out.world = std::make_unique<World>(sceneWorldDef(spec));
  out.rockFall = &attachRockFall(*out.world, sceneRockFallDef(spec, out.world->def().terrain));
  if (out.world->def().terrain)
    out.evaluationLines = sceneEvaluationLines(spec, *out.world->def().terrain);
  const auto shapes = buildSceneShapes(spec);
  BodyAdder bodies{out, {}};
  addSceneBodies(spec, shapes, bodies);
  addEmitterReleases(spec, shapes, bodies);
  addSceneBarriers(spec, bodies);
  checkRunLength(*out.world, spec.duration, spec.limits, bodies.where);
  return out;
}

}  // namespace vf

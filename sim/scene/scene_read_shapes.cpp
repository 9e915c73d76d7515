// [shapes.NAME], [[bodies]] and [[emitters]]: meshes or generated rocks, and the bodies made
// of them.
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "sim/scene/scene_keys.h"
#include "sim/scene/scene_reader.h"
#include "sim/shape/sphere_tree.h"

namespace vf::scene_reading {

namespace {

// Guards against values that parse but cannot be run (allocation of body arrays).
constexpr std::int64_t kMaxEmitterCount = 1000000;

}  // namespace

// --- [shapes.NAME] ------------------------------------------------------------------------

namespace {

// Names the resolved path, and a near-miss file in the same folder when there is one.
[[noreturn]] void failMissingMesh(const Reader& r, const toml::node& n, const fs::path& resolved,
                                  const std::string& given) {
  std::string message = "mesh file not found: '" + resolved.string() + "'";
  if (fs::path(given).is_relative())
    message += " (relative paths resolve against the scene file's folder)";
  std::error_code ec;
  const fs::path folder = resolved.parent_path().empty() ? fs::path(".") : resolved.parent_path();
  if (fs::is_directory(folder, ec)) {
    std::vector<std::string> names;
    for (const auto& entry : fs::directory_iterator(folder, ec)) {
      if (entry.is_regular_file(ec)) names.push_back(entry.path().filename().string());
    }
    std::sort(names.begin(), names.end());  // directory order is unspecified
    if (auto guess = nearestName(resolved.filename().string(), names))
      message += "; did you mean '" + (resolved.parent_path() / *guess).string() + "'?";
  }
  r.fail(n, message);
}

// Guards the load: each variant of a rock family is built (voxelised) when the scene is.
constexpr std::int64_t kMaxRockSeeds = 1000;

// `rock = { class, seed, seeds, size, volume }`; `seeds` (a family's size, 0 without) is
// returned apart, since it makes several shapes of one table.
RockDef readRock(const Reader& r, const toml::node& n, const std::string& label,
                 std::int64_t& seeds) {
  const std::string rockLabel = label + " rock";
  const toml::table& t = r.table(n, "rock");
  r.checkKeys(t, sceneKeysOf("shapes.NAME.rock"), rockLabel);
  RockDef d;
  const toml::node& c = r.require(t, "class", rockLabel);
  d.shapeClass = r.string(c, "rock.class");
  if (!isRockClass(d.shapeClass)) {
    std::string message = "unknown rock class '" + d.shapeClass + "'";
    if (auto guess = nearestName(d.shapeClass, rockClassNames()))
      message += "; did you mean '" + *guess + "'?";
    r.fail(c, message + " (classes: " + joinNames(rockClassNames()) + ")");
  }
  if (const auto* x = t.get("seed")) {
    const std::int64_t seed = r.integer(*x, "rock.seed");
    if (seed < 0) r.fail(*x, "'rock.seed' must be an integer >= 0, got " + std::to_string(seed));
    d.seed = static_cast<std::uint64_t>(seed);
  }
  seeds = 0;
  if (const auto* x = t.get("seeds")) seeds = r.integerInRange(*x, "rock.seeds", 1, kMaxRockSeeds);
  const toml::node* size = t.get("size");
  const toml::node* volume = t.get("volume");
  if (size != nullptr && volume != nullptr)
    r.fail(*volume, "give either 'rock.size' or 'rock.volume' in " + label + ", not both");
  if (size != nullptr && size->is_number()) {
    d.length = r.positive(*size, "rock.size", " m (the longest extent)");
  } else if (size != nullptr) {
    if (!size->is_array())
      r.fail(*size,
             "'rock.size' must be a number (the longest extent) or an array of 3 numbers "
             "[x, y, z] (the extents), got " +
                 typeName(*size));
    d.extents = r.vec3(*size, "rock.size");
    for (int i = 0; i < 3; ++i)
      if (!(d.extents[i] > 0))
        r.fail(*size, "'rock.size' extents must be > 0 m, got " + formatNumber(d.extents[i]));
    const std::string problem = rockExtentsProblem(d.shapeClass, d.extents);
    if (!problem.empty()) r.fail(*size, "'rock.size': " + problem);
  }
  if (volume != nullptr) d.volume = r.positive(*volume, "rock.volume", " m^3");
  return d;
}

// `mesh`: the resolved path of an existing file.
std::string readMeshPath(const Reader& r, const toml::node& meshNode, const fs::path& sceneFolder) {
  const std::string given = r.string(meshNode, "mesh");
  if (given.empty()) r.fail(meshNode, "'mesh' must name a mesh file, got an empty string");
  fs::path resolved(given);
  if (resolved.is_relative()) resolved = sceneFolder / resolved;
  resolved = resolved.lexically_normal();
  std::error_code ec;
  if (!fs::is_regular_file(resolved, ec)) failMissingMesh(r, meshNode, resolved, given);
  return resolved.string();
}

// `density` or `mass`, and for a rock given neither `rock.size` nor `rock.volume`, both: its
// volume is mass / density.
void readMass(const Reader& r, const toml::table& t, const std::string& label, ShapeSpec& s) {
  const toml::node* density = t.get("density");
  const toml::node* mass = t.get("mass");
  const bool rockSized =
      s.rock && (s.rock->extents != Vec3::Zero() || s.rock->length > 0 || s.rock->volume > 0);
  if (s.rock && !rockSized) {
    if (density == nullptr || mass == nullptr)
      r.fail(t,
             "a rock needs a size: give 'rock.size' or 'rock.volume', or both 'mass' and "
             "'density' (its volume is then mass / density) in " +
                 label);
    s.density = r.positive(*density, "density", " kg/m^3");
    s.rock->volume = r.positive(*mass, "mass", " kg") / s.density;
    return;
  }
  if (density != nullptr && mass != nullptr)
    r.fail(*mass, "give either 'density' or 'mass' in " + label + ", not both");
  if (mass != nullptr)
    s.mass = r.positive(*mass, "mass", " kg");
  else
    s.density = r.positive(r.require(t, "density", label), "density", " kg/m^3");
}

// 'scale': one factor, or one per axis [sx, sy, sz], each > 0.
Vec3 readScale(const Reader& r, const toml::node& n) {
  if (n.is_number())
    return Vec3::Constant(r.positive(n, "scale", " (a factor on the mesh file's units)"));
  if (!n.is_array())
    r.fail(n, "'scale' must be a number or an array of 3 numbers [sx, sy, sz], got " + typeName(n));
  const Vec3 scale = r.vec3(n, "scale");
  for (int i = 0; i < 3; ++i) {
    // A zero factor flattens the mesh to no volume; negative ones would mirror it.
    if (!(scale[i] > 0)) r.fail(n, "'scale' factors must be > 0, got " + formatNumber(scale[i]));
  }
  return scale;
}

// 'up': "z" or "y"; true for a y-up mesh.
bool readYUp(const Reader& r, const toml::node& n) {
  const std::string up = r.string(n, "up");
  if (up != "z" && up != "y")
    r.fail(n,
           "'up' must be \"z\" (the default) or \"y\" (a y-up mesh, rotated so y becomes z), got "
           "\"" +
               up + "\"");
  return up == "y";
}

// A rock family's variants: the shape s once per seed, named NAME#k, the rock's seed + k.
std::vector<ShapeSpec> familyVariants(const ShapeSpec& s, std::int64_t seeds) {
  std::vector<ShapeSpec> variants;
  for (std::int64_t k = 0; k < seeds; ++k) {
    ShapeSpec v = s;
    v.name = s.name + "#" + std::to_string(k);
    v.family = s.name;
    v.rock->seed = s.rock->seed + static_cast<std::uint64_t>(k);
    variants.push_back(std::move(v));
  }
  return variants;
}

// One [shapes.NAME] table: one shape, or a rock family's variants (rock.seeds).
std::vector<ShapeSpec> readShape(const Reader& r, const std::string& name, const toml::table& t,
                                 const fs::path& sceneFolder) {
  const std::string label = "[shapes." + name + "]";
  r.checkKeys(t, sceneKeysOf("shapes.NAME"), label);
  ShapeSpec s;
  s.name = name;
  s.where = r.where(t);

  const toml::node* meshNode = t.get("mesh");
  const toml::node* rockNode = t.get("rock");
  if (meshNode != nullptr && rockNode != nullptr)
    r.fail(*rockNode, "give either 'mesh' (a mesh file) or 'rock' (a generated rock) in " + label +
                          ", not both");
  if (meshNode == nullptr && rockNode == nullptr)
    r.fail(t,
           "missing required key 'mesh' (a mesh file) or 'rock' (a generated rock, e.g. "
           "rock = { class = \"compact\", volume = 0.5 }) in " +
               label);
  std::int64_t seeds = 0;
  if (rockNode != nullptr) {
    for (const char* key : {"scale", "up", "repair"})
      if (const auto* n = t.get(key))
        r.fail(*n, "'" + std::string(key) +
                       "' applies to a mesh file; a rock is sized by "
                       "'rock.size' or 'rock.volume' in " +
                       label);
    s.rock = readRock(r, *rockNode, label, seeds);
  } else {
    if (const auto* n = t.get("repair")) s.repair = r.boolean(*n, "repair");
    s.meshPath = readMeshPath(r, *meshNode, sceneFolder);
  }

  if (const auto* n = t.get("scale")) s.scale = readScale(r, *n);
  readMass(r, t, label, s);
  if (const auto* n = t.get("up")) s.yUp = readYUp(r, *n);
  if (const auto* n = t.get("level"))
    s.level = static_cast<int>(r.integerInRange(*n, "level", kMinLevel, kMaxLevel));
  if (const auto* n = t.get("color")) s.color = r.color(*n, "color");
  if (const auto* n = t.get("smooth")) s.smoothDegrees = r.inRange(*n, "smooth", 0, 180);
  if (seeds == 0) return {s};
  return familyVariants(s, seeds);
}

}  // namespace

void readShapes(const Reader& r, const toml::table& t, const fs::path& sceneFolder,
                SceneSpec& spec) {
  // Keep file order: shape indices pick default colours and must not depend on key sorting.
  for (const auto& [k, v] : inFileOrder(t)) {
    const std::string name(k->str());
    if (!v->is_table())
      r.fail(*v, "'shapes." + name + "' must be a table ([shapes." + name +
                     "] with mesh, scale, density), got " + typeName(*v));
    for (ShapeSpec& s : readShape(r, name, *v->as_table(), sceneFolder)) {
      // A family's NAME#k could meet a table quoted as [shapes."NAME#k"].
      for (const ShapeSpec& other : spec.shapes)
        if (other.name == s.name)
          r.fail(*v, "shape '" + s.name + "' is defined twice (a rock family names its rocks " +
                         "NAME#0, NAME#1, ...)");
      spec.shapes.push_back(std::move(s));
    }
  }
}

namespace {

std::string readShapeReference(const Reader& r, const toml::table& t, const std::string& label,
                               const SceneSpec& spec) {
  const toml::node& n = r.require(t, "shape", label);
  const std::string name = r.string(n, "shape");
  if (isShapeName(spec, name)) return name;
  if (const auto members = familyMembers(spec, name); !members.empty())
    r.fail(n, "'" + name + "' is a family of " + std::to_string(members.size()) +
                  " rocks (rock.seeds); name one of them, '" + members.front() + "' to '" +
                  members.back() + "', or draw among them with [ensemble] shapes");
  const auto names = shapeNames(spec);
  std::string message = "unknown shape '" + name + "'";
  if (names.empty()) {
    message += "; no shapes are defined (add a [shapes." + (name.empty() ? "NAME" : name) +
               "] table with mesh and density)";
  } else if (auto guess = nearestName(name, names)) {
    message += "; did you mean '" + *guess + "'?";
  } else {
    message += "; defined shapes: " + joinNames(names);
  }
  r.fail(n, message);
}

}  // namespace

// --- [[bodies]] ---------------------------------------------------------------------------

void readBodies(const Reader& r, const toml::array& bodies, SceneSpec& spec) {
  for (const toml::node& node : bodies) {
    const toml::table& t = *node.as_table();
    const std::string label = "[[bodies]]";
    r.checkKeys(t, sceneKeysOf("bodies"), label);
    BodySpec b;
    b.where = r.where(t);
    b.shape = readShapeReference(r, t, label, spec);
    if (const auto* n = t.get("position")) b.position = r.vec3(*n, "position");
    if (const auto* n = t.get("orientation")) b.orientation = r.quaternion(*n, "orientation");
    if (const auto* n = t.get("velocity")) b.velocity = r.vec3(*n, "velocity");
    if (const auto* n = t.get("angular_velocity"))
      b.angularVelocity = r.vec3(*n, "angular_velocity");
    if (const auto* n = t.get("static")) b.isStatic = r.boolean(*n, "static");
    if (const auto* n = t.get("drop_height"))
      b.dropHeight =
          r.nonNegative(*n, "drop_height", " m (fall height above the surface under the body)");
    if (const auto* n = t.get("color")) b.color = r.color(*n, "color");
    spec.bodies.push_back(std::move(b));
  }
}

// --- [[emitters]] -------------------------------------------------------------------------

namespace {

void readJitter(const Reader& r, const toml::table& t, EmitterSpec& e) {
  r.checkKeys(t, sceneKeysOf("emitters.jitter"), "[[emitters]] jitter");
  if (const auto* n = t.get("position"))
    e.positionJitter = r.nonNegative(*n, "jitter.position", " m (half-size of a cube)");
  if (const auto* n = t.get("direction"))
    e.directionJitter = r.inRange(*n, "jitter.direction", 0, 180);
  if (const auto* n = t.get("orientation"))
    e.randomOrientation = r.boolean(*n, "jitter.orientation");
  if (const auto* n = t.get("seed")) {
    const std::int64_t seed = r.integer(*n, "jitter.seed");
    if (seed < 0) r.fail(*n, "'jitter.seed' must be an integer >= 0, got " + std::to_string(seed));
    e.seed = static_cast<std::uint64_t>(seed);
  }
}

}  // namespace

void readEmitters(const Reader& r, const toml::array& emitters, SceneSpec& spec) {
  for (const toml::node& node : emitters) {
    const toml::table& t = *node.as_table();
    const std::string label = "[[emitters]]";
    r.checkKeys(t, sceneKeysOf("emitters"), label);
    EmitterSpec e;
    e.where = r.where(t);
    e.shape = readShapeReference(r, t, label, spec);
    if (const auto* n = t.get("count"))
      e.count = static_cast<int>(r.integerInRange(*n, "count", 1, kMaxEmitterCount));
    if (const auto* n = t.get("start")) e.start = r.nonNegative(*n, "start", " s");
    if (const auto* n = t.get("interval")) e.interval = r.nonNegative(*n, "interval", " s");

    const toml::node* one = t.get("position");
    const toml::node* many = t.get("positions");
    if (one != nullptr && many != nullptr)
      r.fail(*many, "give either 'position' or 'positions' in [[emitters]], not both");
    if (one == nullptr && many == nullptr)
      r.fail(t, "missing required key 'position' (or 'positions', used in turn) in [[emitters]]");
    if (one != nullptr) {
      e.positions.push_back(r.vec3(*one, "position"));
    } else {
      const toml::array* a = many->as_array();
      if (a == nullptr || a->empty())
        r.fail(*many, "'positions' must be a non-empty array of [x, y, z] arrays, got " +
                          (a == nullptr ? typeName(*many) : std::string("an empty array")));
      for (std::size_t i = 0; i < a->size(); ++i)
        e.positions.push_back(r.vec3(*a->get(i), "positions[" + std::to_string(i) + "]"));
    }

    if (const auto* n = t.get("velocity")) e.velocity = r.vec3(*n, "velocity");
    if (const auto* n = t.get("angular_velocity"))
      e.angularVelocity = r.vec3(*n, "angular_velocity");
    if (const auto* n = t.get("orientation")) e.orientation = r.quaternion(*n, "orientation");
    if (const auto* n = t.get("color")) e.color = r.color(*n, "color");
    if (const auto* n = t.get("jitter")) readJitter(r, r.table(*n, "jitter"), e);
    if (const auto* n = t.get("drop_height"))
      e.dropHeight = r.nonNegative(*n, "drop_height", " m (fall height above what lies below)");
    if (const auto* n = t.get("clear_release")) e.clearRelease = r.boolean(*n, "clear_release");
    spec.emitters.push_back(std::move(e));
  }
}

}  // namespace vf::scene_reading

// Bakes: the header is JSON (nlohmann-json; the only file in sim/ that includes it), the body
// raw little-endian float64 records, so any language reads it with one array view (numpy:
// np.frombuffer(body, '<f8').reshape(records, 1 + 14 * bodies)). Doubles go through JSON as
// their shortest round-trip decimal, so every number reads back bit-exact.
#include "sim/bake.h"

#include <algorithm>
#include <bit>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <utility>

#include "sim/core/error.h"
#include "sim/shape/sphere_tree.h"

namespace vf {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

constexpr char kSignature[] = "VOXFALL-BAKE 1\n";
// 2: the header holds the scene's named cameras ([cameras.NAME]) as well; 1 is still read.
// 3: each shape holds its up axis, repair flag and generated rock; 1 and 2 are still read.
// 4: the scene's [light], the terrain's texture, each shape's `smooth` and each camera's
// `offset_given`; 1 to 3 are still read.
constexpr int kVersion = 4;
constexpr int kValuesPerBody = 14;  // active, x(3), q(w, x, y, z), P(3), L(3)
static_assert(std::endian::native == std::endian::little, "bakes are little-endian float64");

json vec(const Vec3& v) { return json::array({v.x(), v.y(), v.z()}); }

json rockJson(const std::optional<RockDef>& r) {
  if (!r) return nullptr;
  return {{"class", r->shapeClass},
          {"seed", r->seed},
          {"size", vec(r->extents)},
          {"length", r->length},
          {"volume", r->volume}};
}

json color(const std::optional<Color>& c) {
  if (!c) return nullptr;
  return json::array({(*c)[0], (*c)[1], (*c)[2]});
}

// A path as stored: relative to the bake's folder when it can be, so a bake moves with its
// scene folder (another machine, another checkout).
std::string storedPath(const std::string& path, const std::string& bakePath) {
  if (path.empty()) return path;
  const fs::path folder = fs::absolute(fs::path(bakePath)).parent_path();
  std::error_code ec;
  const fs::path rel = fs::proximate(fs::absolute(path), folder, ec);
  return ec ? fs::absolute(path).string() : rel.generic_string();
}

std::string resolvedPath(const std::string& stored, const std::string& bakePath) {
  if (stored.empty() || fs::path(stored).is_absolute()) return stored;
  return (fs::path(bakePath).parent_path() / stored).lexically_normal().string();
}

json summaryJson(const RunSummary& s) {
  return {{"frames", s.frames},
          {"steps", s.totals.steps},
          {"dt_min", s.totals.dtMin},
          {"dt_max", s.totals.dtMax},
          {"wall_seconds", s.wallSeconds},
          {"sphere_tests", s.totals.sphereTests},
          {"contacts", s.totals.contacts},
          {"max_penetration_body_body", s.maxPenetrationBodyBody},
          {"max_penetration_body_ground", s.maxPenetrationBodyGround},
          {"tunnelled", s.tunnelled},
          {"kinetic_energy", s.kineticEnergy},
          {"potential_energy", s.potentialEnergy},
          {"checksum", s.checksumHex()}};
}

// A header integer as T. nlohmann's get<T>() casts whatever number it finds, and a float past
// T's range (5e88 as an int: found by bake_fuzz) is undefined behaviour; so integers only, in
// T's range, else std::domain_error naming the key (readBake wraps it with the file).
template <class T>
T readInteger(const json& j, const char* key) {
  if (j.is_number_unsigned() && std::in_range<T>(j.get<std::uint64_t>()))
    return static_cast<T>(j.get<std::uint64_t>());
  if (j.is_number_integer() && !j.is_number_unsigned() && std::in_range<T>(j.get<std::int64_t>()))
    return static_cast<T>(j.get<std::int64_t>());
  throw std::domain_error(std::string("'") + key + "' must be an integer from " +
                          std::to_string(std::numeric_limits<T>::min()) + " to " +
                          std::to_string(std::numeric_limits<T>::max()) + ", got " + j.dump());
}

Vec3 readVec(const json& j) {
  return Vec3(j.at(0).get<double>(), j.at(1).get<double>(), j.at(2).get<double>());
}

std::optional<Color> readColor(const json& j) {
  if (j.is_null()) return std::nullopt;
  Color c{};
  for (int i = 0; i < 3; ++i) {
    // Read as a double: a double past float's range converted to float is undefined.
    const double v = j.at(i).get<double>();
    if (!(v >= 0 && v <= 1))
      throw std::domain_error("colours must hold numbers in 0..1, got " + j.at(i).dump());
    c[static_cast<std::size_t>(i)] = static_cast<float>(v);
  }
  return c;
}

std::optional<RockDef> readRock(const json& j) {
  if (j.is_null()) return std::nullopt;
  RockDef r;
  r.shapeClass = j.at("class").get<std::string>();
  if (!isRockClass(r.shapeClass))
    throw std::domain_error("unknown rock class '" + r.shapeClass + "'");
  r.seed = j.at("seed").get<std::uint64_t>();
  r.extents = readVec(j.at("size"));
  r.length = j.at("length").get<double>();
  r.volume = j.at("volume").get<double>();
  return r;
}

// A camera as the header stores it: every key of a [camera] or [cameras.NAME] table, resolved.
json cameraJson(const CameraSpec& c) {
  json path = json::array();
  for (const CameraKey& k : c.path)
    path.push_back({{"time", k.time},
                    {"position", vec(k.position)},
                    {"look_at", vec(k.lookAt)},
                    {"fov", k.fovDegrees}});
  return {{"name", c.name},
          {"where", c.where},
          {"given", c.given},
          {"offset_given", c.offsetGiven},
          {"position", vec(c.position)},
          {"look_at", vec(c.lookAt)},
          {"up", vec(c.up)},
          {"fov", c.fovDegrees},
          {"follow", c.followBody ? json(*c.followBody) : json(nullptr)},
          {"follow_group", c.followGroup},
          {"smoothing", c.smoothing},
          {"path", path},
          {"min_pixels", c.minPixels},
          {"trail", c.trailSeconds}};
}

// [light] as the header stores it: its keys resolved, with `null` for an unset sun.
json lightJson(const LightSpec& l) {
  const auto rgb = [](const Color& c) { return json::array({c[0], c[1], c[2]}); };
  return {
      {"azimuth", l.azimuthDegrees ? json(*l.azimuthDegrees) : json(nullptr)},
      {"elevation", l.elevationDegrees ? json(*l.elevationDegrees) : json(nullptr)},
      {"date", l.date ? json::array({l.date->year, l.date->month, l.date->day}) : json(nullptr)},
      {"utc_seconds", l.utcSeconds},
      {"intensity", l.intensity},
      {"color", rgb(l.color)},
      {"sky", rgb(l.sky)},
      {"ambient", rgb(l.ambient)},
      {"where", l.where}};
}

// The inverse of lightJson.
LightSpec readLight(const json& j) {
  LightSpec l;
  if (!j.at("azimuth").is_null()) l.azimuthDegrees = j.at("azimuth").get<double>();
  if (!j.at("elevation").is_null()) l.elevationDegrees = j.at("elevation").get<double>();
  if (const json& d = j.at("date"); !d.is_null())
    l.date = CivilDate{readInteger<int>(d.at(0), "scene.light.date"),
                       readInteger<int>(d.at(1), "scene.light.date"),
                       readInteger<int>(d.at(2), "scene.light.date")};
  l.utcSeconds = j.at("utc_seconds").get<double>();
  l.intensity = j.at("intensity").get<double>();
  const auto required = [&](const char* key) {
    const std::optional<Color> c = readColor(j.at(key));
    if (!c) throw std::domain_error(std::string("'scene.light.") + key + "' must be a colour");
    return *c;
  };
  l.color = required("color");
  l.sky = required("sky");
  l.ambient = required("ambient");
  l.where = j.at("where").get<std::string>();
  return l;
}

// The inverse of cameraJson. `name` and `where` are absent in version 1 (its one camera was
// the scene's [camera]); `offset_given` before version 4, when a given view kept its offset.
CameraSpec readCamera(const json& j) {
  CameraSpec c;
  c.name = j.value("name", c.name);
  c.where = j.value("where", c.where);
  c.given = j.at("given").get<bool>();
  c.offsetGiven = j.value("offset_given", c.given);
  c.position = readVec(j.at("position"));
  c.lookAt = readVec(j.at("look_at"));
  c.up = readVec(j.at("up"));
  c.fovDegrees = j.at("fov").get<double>();
  if (!j.at("follow").is_null()) c.followBody = readInteger<int>(j.at("follow"), "follow");
  for (const json& id : j.at("follow_group"))
    c.followGroup.push_back(readInteger<int>(id, "follow_group"));
  c.smoothing = j.at("smoothing").get<double>();
  for (const json& k : j.at("path"))
    c.path.push_back(CameraKey{k.at("time").get<double>(), readVec(k.at("position")),
                               readVec(k.at("look_at")), k.at("fov").get<double>()});
  c.minPixels = j.at("min_pixels").get<double>();
  c.trailSeconds = j.at("trail").get<double>();
  return c;
}

RunSummary readSummary(const json& j) {
  RunSummary s;
  s.frames = readInteger<int>(j.at("frames"), "summary.frames");
  s.totals.steps = readInteger<std::uint64_t>(j.at("steps"), "summary.steps");
  s.totals.dtMin = j.at("dt_min").get<double>();
  s.totals.dtMax = j.at("dt_max").get<double>();
  s.wallSeconds = j.at("wall_seconds").get<double>();
  s.totals.sphereTests = readInteger<std::uint64_t>(j.at("sphere_tests"), "summary.sphere_tests");
  s.totals.contacts = readInteger<std::uint64_t>(j.at("contacts"), "summary.contacts");
  s.maxPenetrationBodyBody = j.at("max_penetration_body_body").get<double>();
  s.maxPenetrationBodyGround = j.at("max_penetration_body_ground").get<double>();
  s.tunnelled = readInteger<int>(j.at("tunnelled"), "summary.tunnelled");
  s.kineticEnergy = j.at("kinetic_energy").get<double>();
  s.potentialEnergy = j.at("potential_energy").get<double>();
  const std::string checksum = j.at("checksum").get<std::string>();
  const auto [at, ec] =
      std::from_chars(checksum.data(), checksum.data() + checksum.size(), s.checksum, 16);
  if (ec != std::errc() || at != checksum.data() + checksum.size() || checksum.size() != 16)
    throw std::domain_error("'summary.checksum' must be 16 hexadecimal digits, got '" + checksum +
                            "'");
  return s;
}

}  // namespace

std::vector<std::shared_ptr<const Shape>> bakeShapes(const Bake& bake) {
  std::map<std::string, TriMesh> meshes;  // by shapeMeshKey
  std::vector<std::shared_ptr<const Shape>> shapes;
  for (const ShapeSpec& s : bake.scene.shapes) {
    const std::string key = shapeMeshKey(s);
    auto mesh = meshes.find(key);
    if (mesh == meshes.end()) mesh = meshes.emplace(key, shapeSourceMesh(s)).first;
    auto shape = std::make_shared<Shape>();
    shape->name = s.name;
    // centredMesh() is bit-identical to the mesh makeShape() keeps (shape.h).
    shape->mesh = centredMesh(mesh->second, shapeScale(s));
    double farthest = 0;
    for (const Vec3& v : shape->mesh.vertices) farthest = std::max(farthest, v.norm());
    shape->diameter = 2 * farthest;
    shapes.push_back(std::move(shape));
  }
  return shapes;
}

Bake bakeHeader(const SceneSpec& spec, const BuiltScene& built) {
  Bake bake;
  bake.scene = spec;
  bake.scene.bodies.clear();
  bake.scene.emitters.clear();
  const World& world = *built.world;
  for (int id = 0; id < world.bodyCount(); ++id) {
    BakeBody b;
    const auto shape = std::find_if(
        spec.shapes.begin(), spec.shapes.end(),
        [&](const ShapeSpec& s) { return s.name == built.shapeOf[static_cast<std::size_t>(id)]; });
    VF_ASSERT(shape != spec.shapes.end());
    b.shape = static_cast<int>(shape - spec.shapes.begin());
    b.color = built.colors[static_cast<std::size_t>(id)];
    b.isStatic = world.isStatic(id);
    if (!b.isStatic) {
      b.invMass = 1.0 / world.shape(id).mass;
      b.inertiaBodyInv = world.shape(id).inertiaBodyInv;
    }
    bake.bodies.push_back(b);
  }
  return bake;
}

void addBakeRecord(Bake& bake, const World& world) {
  BakeRecord r;
  r.time = world.time();
  r.states.reserve(static_cast<std::size_t>(world.bodyCount()));
  for (int id = 0; id < world.bodyCount(); ++id) {
    r.states.push_back(world.state(id));
    r.active.push_back(world.isActive(id) ? 1 : 0);
  }
  bake.records.push_back(std::move(r));
}

std::vector<BodyState> Bake::statesAt(double t, std::vector<char>& active) const {
  VF_ASSERT(!records.empty());
  // The last record at or before t, with World::advanceTo's tolerance.
  auto after = std::upper_bound(records.begin(), records.end(), t + kTimeTolerance,
                                [](double v, const BakeRecord& r) { return v < r.time; });
  const BakeRecord& r = after == records.begin() ? records.front() : *std::prev(after);
  return sampleSteps(r, after == records.end() || after == records.begin() ? nullptr : &*after, t,
                     active);
}

void writeBake(std::FILE* out, const std::string& bakePath, const Bake& bake) {
  const SceneSpec& s = bake.scene;
  json shapes = json::array();
  for (const ShapeSpec& shape : s.shapes)
    shapes.push_back(
        {{"name", shape.name},
         {"mesh", storedPath(shape.meshPath, bakePath)},
         {"scale", vec(shape.scale)},
         {"density", shape.density},
         {"level", shape.level.value_or(s.level)},
         {"color", color(shape.color)},
         {"up", shape.yUp ? "y" : "z"},
         {"repair", shape.repair},
         {"rock", rockJson(shape.rock)},
         {"smooth", shape.smoothDegrees ? json(*shape.smoothDegrees) : json(nullptr)}});
  json bodies = json::array();
  for (const BakeBody& b : bake.bodies) {
    json inertia = json::array();
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) inertia.push_back(b.inertiaBodyInv(r, c));
    bodies.push_back({{"shape", b.shape},
                      {"color", color(b.color)},
                      {"static", b.isStatic},
                      {"inv_mass", b.invMass},
                      {"inertia_body_inv", inertia}});
  }
  json cameras = json::array();
  for (const CameraSpec& c : s.cameras) cameras.push_back(cameraJson(c));
  const json header = {{"format", "voxfall-bake"},
                       {"version", kVersion},
                       {"scene",
                        {{"path", storedPath(s.path, bakePath)},
                         {"name", s.name},
                         {"duration", s.duration},
                         {"fps", s.fps},
                         {"gravity", vec(s.gravity)},
                         {"ground_plane", s.groundPlane ? json(*s.groundPlane) : json(nullptr)},
                         {"terrain", storedPath(s.terrainPath, bakePath)},
                         {"terrain_offset", vec(s.terrainShift)},
                         {"terrain_texture", storedPath(s.terrainTexturePath, bakePath)},
                         {"light", lightJson(s.light)},
                         {"camera", cameraJson(s.camera)},
                         {"cameras", cameras},
                         {"output",
                          {{"width", s.output.width},
                           {"height", s.output.height},
                           {"crf", s.output.crf},
                           {"speed", s.output.speed},
                           {"alpha", s.output.alpha},
                           {"overlay_time", s.output.overlayTime},
                           {"overlay_scale", s.output.overlayScale}}}}},
                       {"shapes", shapes},
                       {"bodies", bodies},
                       {"summary", bake.summary ? summaryJson(*bake.summary) : json(nullptr)},
                       {"records", bake.records.size()}};
  std::fputs(kSignature, out);
  const std::string text = header.dump();
  std::fwrite(text.data(), 1, text.size(), out);
  std::fputc('\n', out);
  std::vector<double> row(1 + kValuesPerBody * bake.bodies.size());
  for (const BakeRecord& r : bake.records) {
    std::size_t n = 0;
    row[n++] = r.time;
    for (std::size_t i = 0; i < bake.bodies.size(); ++i) {
      const BodyState& y = r.states[i];
      for (double v : {r.active[i] ? 1.0 : 0.0, y.x.x(), y.x.y(), y.x.z(), y.q.w(), y.q.x(),
                       y.q.y(), y.q.z(), y.P.x(), y.P.y(), y.P.z(), y.L.x(), y.L.y(), y.L.z()})
        row[n++] = v;
    }
    std::fwrite(row.data(), sizeof(double), row.size(), out);
  }
}

bool isBakeFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  char head[sizeof kSignature - 1] = {};
  in.read(head, sizeof head);
  return in && std::memcmp(head, kSignature, sizeof head) == 0;
}

// The values a bake's header may hold: what a scene file may give (scene_loader.cpp) and what a
// run writes. A header edited by hand or damaged gets the first problem, named by its key in
// the header, instead of a drawing of nonsense or an allocation that fails. (Colours and
// integers are checked as they are read: readColor, readInteger.)
void checkHeader(const Bake& bake, const std::string& where) {
  const auto fail = [&](const std::string& key, const std::string& rule, double got) {
    char value[64];
    std::snprintf(value, sizeof value, "%.17g", got);
    throw InputError(where, "bad bake header: '" + key + "' " + rule + ", got " + value);
  };
  const auto positive = [&](const std::string& key, double v) {
    if (!(std::isfinite(v) && v > 0)) fail(key, "must be a finite number > 0", v);
  };
  const auto nonNegative = [&](const std::string& key, double v) {
    if (!(std::isfinite(v) && v >= 0)) fail(key, "must be a finite number >= 0", v);
  };
  const auto finite = [&](const std::string& key, double v) {
    if (!std::isfinite(v)) fail(key, "must be finite", v);
  };
  const auto finiteAll = [&](const std::string& key, const auto& v) {  // a vector or matrix
    for (const double x : v.reshaped())
      if (!std::isfinite(x)) fail(key, "must hold finite numbers", x);
  };
  const auto fov = [&](const std::string& key, double v) {
    if (!(v > 0 && v < 180)) fail(key, "must be in degrees, 0 < fov < 180", v);
  };
  const SceneSpec& s = bake.scene;
  positive("scene.duration", s.duration);
  positive("scene.fps", s.fps);
  if (s.duration * s.fps > kMaxSceneFrames)
    fail("scene.duration", "times fps must be at most 1e7 frames", s.duration);
  positive("scene.output.speed", s.output.speed);
  if (s.duration * s.fps / s.output.speed > kMaxSceneFrames)
    fail("scene.output.speed", "makes more than 1e7 frames of duration * fps / speed",
         s.output.speed);
  finiteAll("scene.gravity", s.gravity);
  finiteAll("scene.terrain_offset", s.terrainShift);
  if (s.groundPlane) finite("scene.ground_plane", *s.groundPlane);
  for (const auto& [side, pixels] :
       {std::pair{"width", s.output.width}, {"height", s.output.height}})
    if (const std::string problem = frameSideProblem(side, pixels); !problem.empty())
      throw InputError(where, "bad bake header: scene.output: " + problem);
  if (s.output.crf < 0 || s.output.crf > 51)
    fail("scene.output.crf", "must be 0..51", s.output.crf);
  // Keys are named by their place in the header's JSON.
  std::vector<std::pair<std::string, const CameraSpec*>> cameras{{"scene.camera.", &s.camera}};
  for (std::size_t i = 0; i < s.cameras.size(); ++i)
    cameras.emplace_back("scene.cameras[" + std::to_string(i) + "].", &s.cameras[i]);
  const int bodies = static_cast<int>(bake.bodies.size());
  for (const auto& [key, c] : cameras) {
    finiteAll(key + "position", c->position);
    finiteAll(key + "look_at", c->lookAt);
    finiteAll(key + "up", c->up);
    if (!(c->up.norm() > 0)) fail(key + "up", "must be a non-zero vector", 0);
    fov(key + "fov", c->fovDegrees);
    nonNegative(key + "smoothing", c->smoothing);
    nonNegative(key + "min_pixels", c->minPixels);
    nonNegative(key + "trail", c->trailSeconds);
    std::vector<int> followed = c->followGroup;
    if (c->followBody) followed.push_back(*c->followBody);
    for (const int id : followed)
      if (id < 0 || id >= bodies) fail(key + "follow", "must name a body of the bake", id);
    for (const CameraKey& k : c->path) {
      finite(key + "path[].time", k.time);
      finiteAll(key + "path[].position", k.position);
      finiteAll(key + "path[].look_at", k.lookAt);
      fov(key + "path[].fov", k.fovDegrees);
    }
  }
  const LightSpec& light = s.light;
  if (light.azimuthDegrees.has_value() != light.elevationDegrees.has_value())
    fail("scene.light.azimuth", "and 'elevation' must both be numbers or both null", 0);
  if (light.azimuthDegrees) finite("scene.light.azimuth", *light.azimuthDegrees);
  if (light.elevationDegrees && !(*light.elevationDegrees > 0 && *light.elevationDegrees <= 90))
    fail("scene.light.elevation", "must be above 0 and at most 90 degrees",
         *light.elevationDegrees);
  if (light.date && (light.date->month < 1 || light.date->month > 12 || light.date->day < 1 ||
                     light.date->day > 31 || light.date->year < 1800 || light.date->year > 2200))
    fail("scene.light.date", "must be a date [year, month, day] in 1800..2200", light.date->year);
  if (!(light.utcSeconds >= 0 && light.utcSeconds < 86400))
    fail("scene.light.utc_seconds", "must be 0 <= s < 86400", light.utcSeconds);
  if (!(light.intensity >= 0 && light.intensity <= 100))
    fail("scene.light.intensity", "must be 0..100", light.intensity);
  for (std::size_t i = 0; i < s.shapes.size(); ++i) {
    const ShapeSpec& shape = s.shapes[i];
    const std::string key = "shapes[" + std::to_string(i) + "].";
    if (shape.smoothDegrees && !(*shape.smoothDegrees >= 0 && *shape.smoothDegrees <= 180))
      fail(key + "smooth", "must be 0..180 degrees", *shape.smoothDegrees);
    for (int i = 0; i < 3; ++i) positive(key + "scale", shape.scale[i]);
    nonNegative(key + "density", shape.density);  // 0: the scene gave the shape's mass
    if (const auto& r = shape.rock) {
      // Exactly one size, as the scene loader leaves it; the generator asserts as much.
      const int sizes = (r->extents != Vec3::Zero()) + (r->length != 0) + (r->volume != 0);
      if (sizes != 1) fail(key + "rock", "must give one of size, length and volume", sizes);
      if (r->extents != Vec3::Zero())
        for (int k = 0; k < 3; ++k) positive(key + "rock.size", r->extents[k]);
      if (r->length != 0) positive(key + "rock.length", r->length);
      if (r->volume != 0) positive(key + "rock.volume", r->volume);
    }
    const int level = shape.level.value_or(kMinLevel);
    if (level < kMinLevel || level > kMaxLevel)
      fail(key + "level", "must be " + std::to_string(kMinLevel) + ".." + std::to_string(kMaxLevel),
           level);
  }
  for (int i = 0; i < bodies; ++i) {
    const BakeBody& b = bake.bodies[static_cast<std::size_t>(i)];
    const std::string key = "bodies[" + std::to_string(i) + "].";
    nonNegative(key + "inv_mass", b.invMass);
    finiteAll(key + "inertia_body_inv", b.inertiaBodyInv);
  }
}

Bake readBake(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, "cannot open the bake");
  const std::string data((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::size_t sig = sizeof kSignature - 1;
  if (data.compare(0, sig, kSignature) != 0)
    throw InputError(path, "not a voxfall bake (no 'VOXFALL-BAKE 1' first line)");
  const std::size_t end = data.find('\n', sig);
  if (end == std::string::npos) throw InputError(path + ":2", "bake header has no end of line");
  Bake bake;
  std::size_t records = 0;
  try {
    const json h = json::parse(data.begin() + static_cast<std::ptrdiff_t>(sig),
                               data.begin() + static_cast<std::ptrdiff_t>(end));
    if (h.at("format") != "voxfall-bake")
      throw InputError(path + ":2", "not a voxfall bake header (format is not \"voxfall-bake\")");
    const int version = readInteger<int>(h.at("version"), "version");
    if (version < 1 || version > kVersion)
      throw InputError(path + ":2", "bake version " + std::to_string(version) +
                                        " is not one this voxfall reads (1.." +
                                        std::to_string(kVersion) + ")");
    const json& sc = h.at("scene");
    SceneSpec& s = bake.scene;
    s.path = resolvedPath(sc.at("path").get<std::string>(), path);
    s.name = sc.at("name").get<std::string>();
    s.duration = sc.at("duration").get<double>();
    s.fps = sc.at("fps").get<double>();
    s.gravity = readVec(sc.at("gravity"));
    if (!sc.at("ground_plane").is_null()) s.groundPlane = sc.at("ground_plane").get<double>();
    s.terrainPath = resolvedPath(sc.at("terrain").get<std::string>(), path);
    s.terrainShift = readVec(sc.at("terrain_offset"));
    if (version >= 4) {
      s.terrainTexturePath = resolvedPath(sc.at("terrain_texture").get<std::string>(), path);
      s.light = readLight(sc.at("light"));
    }
    s.camera = readCamera(sc.at("camera"));
    // Version 1 kept only the scene's [camera]: such a bake has no named cameras.
    if (version >= 2)
      for (const json& c : sc.at("cameras")) s.cameras.push_back(readCamera(c));
    const json& o = sc.at("output");
    s.output.width = readInteger<int>(o.at("width"), "scene.output.width");
    s.output.height = readInteger<int>(o.at("height"), "scene.output.height");
    s.output.crf = readInteger<int>(o.at("crf"), "scene.output.crf");
    // Bakes written before these keys existed draw as they did: speed 1, opaque, no overlay.
    if (o.contains("speed")) s.output.speed = o.at("speed").get<double>();
    if (o.contains("alpha")) s.output.alpha = o.at("alpha").get<bool>();
    if (o.contains("overlay_time")) s.output.overlayTime = o.at("overlay_time").get<bool>();
    if (o.contains("overlay_scale")) s.output.overlayScale = o.at("overlay_scale").get<bool>();
    for (const json& j : h.at("shapes")) {
      ShapeSpec shape;
      shape.name = j.at("name").get<std::string>();
      shape.meshPath = resolvedPath(j.at("mesh").get<std::string>(), path);
      shape.scale = readVec(j.at("scale"));
      shape.density = j.at("density").get<double>();
      shape.level = readInteger<int>(j.at("level"), "shapes[].level");
      shape.color = readColor(j.at("color"));
      if (version >= 3) {  // 1 and 2 had z-up meshes as the files hold them, and no rocks
        shape.yUp = j.at("up").get<std::string>() == "y";
        shape.repair = j.at("repair").get<bool>();
        shape.rock = readRock(j.at("rock"));
      }
      if (version >= 4 && !j.at("smooth").is_null())
        shape.smoothDegrees = j.at("smooth").get<double>();
      s.shapes.push_back(shape);
    }
    for (const json& j : h.at("bodies")) {
      BakeBody b;
      b.shape = readInteger<int>(j.at("shape"), "bodies[].shape");
      if (b.shape < 0 || b.shape >= static_cast<int>(s.shapes.size()))
        throw InputError(path + ":2", "a body names shape " + std::to_string(b.shape) +
                                          ", but there are " + std::to_string(s.shapes.size()));
      b.color = readColor(j.at("color")).value_or(b.color);
      b.isStatic = j.at("static").get<bool>();
      b.invMass = j.at("inv_mass").get<double>();
      const json& m = j.at("inertia_body_inv");
      for (int r = 0; r < 3; ++r)
        for (int k = 0; k < 3; ++k) b.inertiaBodyInv(r, k) = m.at(3 * r + k).get<double>();
      bake.bodies.push_back(b);
    }
    if (const json& summary = h.at("summary"); !summary.is_null())
      bake.summary = readSummary(summary);
    records = readInteger<std::size_t>(h.at("records"), "records");
  } catch (const json::exception& e) {
    throw InputError(path + ":2", std::string("bad bake header: ") + e.what());
  } catch (const std::domain_error& e) {
    throw InputError(path + ":2", std::string("bad bake header: ") + e.what());
  }
  checkHeader(bake, path + ":2");
  const std::size_t width = 1 + kValuesPerBody * bake.bodies.size();
  const std::size_t body = data.size() - end - 1;
  // Divided, not multiplied: a record count near 2^64 / width would wrap to the body's size.
  if (records == 0 || body % (width * sizeof(double)) != 0 ||
      records != body / (width * sizeof(double)))
    throw InputError(path, "the bake body holds " + std::to_string(body) + " bytes, not the " +
                               std::to_string(records) + " records of " + std::to_string(width) +
                               " float64 its header announces");
  const char* p = data.data() + end + 1;
  std::vector<double> row(width);
  bake.records.resize(records);
  for (std::size_t k = 0; k < records; ++k) {
    BakeRecord& r = bake.records[k];
    std::memcpy(row.data(), p, width * sizeof(double));
    p += width * sizeof(double);
    // What a run writes: finite numbers, flags of 0 or 1, unit quaternions (to rounding; the
    // integrator normalises them every step). Anything else is a damaged file, which would
    // draw nothing and export NaN into glTF.
    const auto damaged = [&](const std::string& what) {
      return InputError(path, "record " + std::to_string(k) + ": " + what +
                                  "; the bake is damaged (simulate the scene again)");
    };
    for (std::size_t j = 0; j < width; ++j)
      if (!std::isfinite(row[j]))
        throw damaged(j == 0 ? "the time is not finite"
                             : "body " + std::to_string((j - 1) / kValuesPerBody) +
                                   "'s state holds a value that is not finite");
    r.time = row[0];
    r.states.resize(bake.bodies.size());
    r.active.resize(bake.bodies.size());
    for (std::size_t i = 0; i < bake.bodies.size(); ++i) {
      const double* v = &row[1 + kValuesPerBody * i];
      const double qNorm = std::sqrt(v[4] * v[4] + v[5] * v[5] + v[6] * v[6] + v[7] * v[7]);
      if ((v[0] != 0 && v[0] != 1) || std::abs(qNorm - 1) > 1e-6)
        throw damaged("body " + std::to_string(i) +
                      (v[0] != 0 && v[0] != 1 ? "'s active flag is not 0 or 1"
                                              : "'s orientation is not a unit quaternion"));
      r.active[i] = v[0] != 0 ? 1 : 0;
      r.states[i].x = Vec3(v[1], v[2], v[3]);
      r.states[i].q = Quat(v[4], v[5], v[6], v[7]);
      r.states[i].P = Vec3(v[8], v[9], v[10]);
      r.states[i].L = Vec3(v[11], v[12], v[13]);
    }
  }
  for (std::size_t i = 1; i < bake.records.size(); ++i)
    if (!(bake.records[i].time > bake.records[i - 1].time))
      throw InputError(path, "record " + std::to_string(i) + " does not come after the one before");
  return bake;
}

}  // namespace vf

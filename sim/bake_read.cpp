// Reading a bake back (format: docs/output-formats.md, "Bake files"): the JSON header
// (nlohmann-json), then the float64 records. A damaged or hand-edited file gets one error
// naming the file and what is wrong, never a drawing of nonsense.
#include <charconv>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <nlohmann/json.hpp>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "sim/bake.h"
#include "sim/bake_format.h"
#include "sim/core/error.h"

namespace vf {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

std::string resolvedPath(const std::string& stored, const std::string& bakePath) {
  if (stored.empty() || fs::path(stored).is_absolute()) return stored;
  return (fs::path(bakePath).parent_path() / stored).lexically_normal().string();
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

// The header's scene table, its paths resolved against the bake's folder (shapes apart).
SceneSpec readScene(const json& sc, int version, const std::string& path) {
  SceneSpec s;
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
  return s;
}

ShapeSpec readShape(const json& j, int version, const std::string& path) {
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
  if (version >= 4 && !j.at("smooth").is_null()) shape.smoothDegrees = j.at("smooth").get<double>();
  return shape;
}

BakeBody readBody(const json& j, std::size_t shapes, const std::string& path) {
  BakeBody b;
  b.shape = readInteger<int>(j.at("shape"), "bodies[].shape");
  if (b.shape < 0 || b.shape >= static_cast<int>(shapes))
    throw InputError(path + ":2", "a body names shape " + std::to_string(b.shape) +
                                      ", but there are " + std::to_string(shapes));
  b.color = readColor(j.at("color")).value_or(b.color);
  b.isStatic = j.at("static").get<bool>();
  b.invMass = j.at("inv_mass").get<double>();
  const json& m = j.at("inertia_body_inv");
  for (int r = 0; r < 3; ++r)
    for (int k = 0; k < 3; ++k) b.inertiaBodyInv(r, k) = m.at(3 * r + k).get<double>();
  return b;
}

// The header line (between `begin` and `end` of the file's text) into `bake`; returns the
// number of records it announces.
std::size_t readHeader(std::string::const_iterator begin, std::string::const_iterator end,
                       const std::string& path, Bake& bake) {
  try {
    const json h = json::parse(begin, end);
    if (h.at("format") != "voxfall-bake")
      throw InputError(path + ":2", "not a voxfall bake header (format is not \"voxfall-bake\")");
    const int version = readInteger<int>(h.at("version"), "version");
    if (version < 1 || version > kBakeVersion)
      throw InputError(path + ":2", "bake version " + std::to_string(version) +
                                        " is not one this voxfall reads (1.." +
                                        std::to_string(kBakeVersion) + ")");
    bake.scene = readScene(h.at("scene"), version, path);
    for (const json& j : h.at("shapes")) bake.scene.shapes.push_back(readShape(j, version, path));
    for (const json& j : h.at("bodies"))
      bake.bodies.push_back(readBody(j, bake.scene.shapes.size(), path));
    if (const json& summary = h.at("summary"); !summary.is_null())
      bake.summary = readSummary(summary);
    return readInteger<std::size_t>(h.at("records"), "records");
  } catch (const json::exception& e) {
    throw InputError(path + ":2", std::string("bad bake header: ") + e.what());
  } catch (const std::domain_error& e) {
    throw InputError(path + ":2", std::string("bad bake header: ") + e.what());
  }
}

// Record k from its row of floats. What a run writes: finite numbers, flags of 0 or 1, unit
// quaternions (to rounding; the integrator normalises them every step). Anything else is a
// damaged file, which would draw nothing and export NaN into glTF.
BakeRecord readRecord(const std::vector<double>& row, std::size_t k, std::size_t bodies,
                      const std::string& path) {
  const auto damaged = [&](const std::string& what) {
    return InputError(path, "record " + std::to_string(k) + ": " + what +
                                "; the bake is damaged (simulate the scene again)");
  };
  for (std::size_t j = 0; j < row.size(); ++j)
    if (!std::isfinite(row[j]))
      throw damaged(j == 0 ? "the time is not finite"
                           : "body " + std::to_string((j - 1) / kBakeValuesPerBody) +
                                 "'s state holds a value that is not finite");
  BakeRecord r;
  r.time = row[0];
  r.states.resize(bodies);
  r.active.resize(bodies);
  for (std::size_t i = 0; i < bodies; ++i) {
    const double* v = &row[1 + kBakeValuesPerBody * i];
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
  return r;
}

// The records after the header line (the file's text from `body` on), as many as announced.
void readRecords(const std::string& data, std::size_t body, std::size_t records,
                 const std::string& path, Bake& bake) {
  const std::size_t width = 1 + kBakeValuesPerBody * bake.bodies.size();
  const std::size_t bytes = data.size() - body;
  // Divided, not multiplied: a record count near 2^64 / width would wrap to the body's size.
  if (records == 0 || bytes % (width * sizeof(double)) != 0 ||
      records != bytes / (width * sizeof(double)))
    throw InputError(path, "the bake body holds " + std::to_string(bytes) + " bytes, not the " +
                               std::to_string(records) + " records of " + std::to_string(width) +
                               " float64 its header announces");
  const char* p = data.data() + body;
  std::vector<double> row(width);
  bake.records.resize(records);
  for (std::size_t k = 0; k < records; ++k) {
    std::memcpy(row.data(), p, width * sizeof(double));
    p += width * sizeof(double);
    bake.records[k] = readRecord(row, k, bake.bodies.size(), path);
  }
  for (std::size_t i = 1; i < bake.records.size(); ++i)
    if (!(bake.records[i].time > bake.records[i - 1].time))
      throw InputError(path, "record " + std::to_string(i) + " does not come after the one before");
}

}  // namespace

bool isBakeFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  char head[sizeof kBakeSignature - 1] = {};
  in.read(head, sizeof head);
  return in && std::memcmp(head, kBakeSignature, sizeof head) == 0;
}

Bake readBake(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, "cannot open the bake");
  const std::string data((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::size_t sig = sizeof kBakeSignature - 1;
  if (data.compare(0, sig, kBakeSignature) != 0)
    throw InputError(path, "not a voxfall bake (no 'VOXFALL-BAKE 1' first line)");
  const std::size_t end = data.find('\n', sig);
  if (end == std::string::npos) throw InputError(path + ":2", "bake header has no end of line");
  Bake bake;
  const std::size_t records =
      readHeader(data.begin() + static_cast<std::ptrdiff_t>(sig),
                 data.begin() + static_cast<std::ptrdiff_t>(end), path, bake);
  checkBakeHeader(bake, path + ":2");
  readRecords(data, end + 1, records, path, bake);
  return bake;
}

}  // namespace vf

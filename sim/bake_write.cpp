// Writing a bake: the header is JSON (nlohmann-json, here and in bake_read.cpp only), the body
// raw little-endian float64 records, so any language reads it with one array view (numpy:
// np.frombuffer(body, '<f8').reshape(records, 1 + 14 * bodies)). Doubles go through JSON as
// their shortest round-trip decimal, so every number reads back bit-exact.
#include <bit>
#include <cstdio>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "sim/bake.h"
#include "sim/bake_format.h"

namespace vf {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

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

}  // namespace

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
                       {"version", kBakeVersion},
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
  std::fputs(kBakeSignature, out);
  const std::string text = header.dump();
  std::fwrite(text.data(), 1, text.size(), out);
  std::fputc('\n', out);
  std::vector<double> row(1 + kBakeValuesPerBody * bake.bodies.size());
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

}  // namespace vf

// [camera], [cameras.NAME], [output] and [light]: what the renderer is told to draw.
#include <cstdint>
#include <string>
#include <vector>

#include "sim/scene/scene_keys.h"
#include "sim/scene/scene_reader.h"

namespace vf::scene_reading {

// --- [camera], [output] -------------------------------------------------------------------

namespace {

// A body index for `follow`: [[bodies]] in file order, then each emitter's releases in turn.
int readBodyIndex(const Reader& r, const toml::node& n, const std::string& name,
                  const SceneSpec& spec) {
  std::int64_t total = static_cast<std::int64_t>(spec.bodies.size());
  for (const auto& e : spec.emitters) total += e.count;
  const std::int64_t id = r.integer(n, name);
  if (id < 0 || id >= total)
    r.fail(n, "'" + name + "' must be a body index from 0 to " + std::to_string(total - 1) +
                  " ([[bodies]] in order, then the emitters' bodies), got " + std::to_string(id) +
                  (total == 0 ? " (the scene has no bodies)" : ""));
  return static_cast<int>(id);
}

double readFov(const Reader& r, const toml::node& n, const std::string& name) {
  const double fov = r.number(n, name);
  if (!(fov > 0 && fov < 180))
    r.fail(n, "'" + name + "' must be a vertical field of view in degrees, > 0 and < 180, got " +
                  formatNumber(fov));
  return fov;
}

// `path = [{ time = 0, position = [...], look_at = [...], fov = 40 }, ...]`: times increase;
// fov defaults to the camera's.
void readCameraPath(const Reader& r, const toml::node& n, const std::string& keysPath,
                    CameraSpec& c) {
  const toml::array* keys = n.as_array();
  if (keys == nullptr || keys->empty())
    r.fail(n, "'path' must be an array of keys {time, position, look_at, fov}, got " + typeName(n));
  for (std::size_t i = 0; i < keys->size(); ++i) {
    const std::string label = "path[" + std::to_string(i) + "]";
    const toml::table& k = r.table(*keys->get(i), label);
    r.checkKeys(k, sceneKeysOf(keysPath + ".path"), label);
    CameraKey key;
    key.time = r.nonNegative(r.require(k, "time", label), "time", " s");
    key.position = r.vec3(r.require(k, "position", label), "position");
    key.lookAt = r.vec3(r.require(k, "look_at", label), "look_at");
    key.fovDegrees = c.fovDegrees;
    if (const auto* f = k.get("fov")) key.fovDegrees = readFov(r, *f, "fov");
    if (!((key.lookAt - key.position).norm() > 0))
      r.fail(k, "'look_at' must differ from 'position' in " + label);
    if (!c.path.empty() && !(key.time > c.path.back().time))
      r.fail(*k.get("time"), "path key times must increase, got " + formatNumber(key.time) +
                                 " after " + formatNumber(c.path.back().time));
    c.path.push_back(key);
  }
}

}  // namespace

// [camera] and [cameras.NAME] share their keys.
CameraSpec readCamera(const Reader& r, const toml::table& t, const std::string& name,
                      const std::string& label, const SceneSpec& spec) {
  const std::string keysPath = name == "camera" ? "camera" : "cameras.NAME";
  r.checkKeys(t, sceneKeysOf(keysPath), label);
  CameraSpec c;
  c.name = name;
  c.where = r.where(t);
  // A view is given by any of these; a table with only trail or min_pixels keeps the
  // automatic camera, and a path replaces the fixed view.
  c.given = t.get("path") == nullptr && (t.get("position") || t.get("look_at") || t.get("up") ||
                                         t.get("fov") || t.get("follow"));
  c.offsetGiven = t.get("position") || t.get("look_at");
  if (const auto* n = t.get("position")) c.position = r.vec3(*n, "position");
  if (const auto* n = t.get("look_at")) c.lookAt = r.vec3(*n, "look_at");
  if (const auto* n = t.get("up")) {
    c.up = r.vec3(*n, "up");
    if (!(c.up.norm() > 0)) r.fail(*n, "'up' must be a non-zero vector, e.g. [0, 0, 1]");
  }
  if (const auto* n = t.get("fov")) c.fovDegrees = readFov(r, *n, "fov");
  if (const auto* n = t.get("follow")) {
    if (const toml::array* group = n->as_array()) {
      if (group->empty()) r.fail(*n, "'follow' must be a body index or a non-empty array of them");
      for (std::size_t i = 0; i < group->size(); ++i)
        c.followGroup.push_back(
            readBodyIndex(r, *group->get(i), "follow[" + std::to_string(i) + "]", spec));
    } else {
      c.followBody = readBodyIndex(r, *n, "follow", spec);
    }
  }
  if (const auto* n = t.get("smoothing")) c.smoothing = r.nonNegative(*n, "smoothing", " s");
  if (const auto* n = t.get("min_pixels")) c.minPixels = r.inRange(*n, "min_pixels", 0, 256);
  if (const auto* n = t.get("trail")) c.trailSeconds = r.nonNegative(*n, "trail", " s");
  if (const auto* n = t.get("path")) {
    if (t.get("follow")) r.fail(*n, "a camera has either a 'path' or 'follow', not both");
    readCameraPath(r, *n, keysPath, c);
  }
  const bool follows = c.followBody || !c.followGroup.empty();
  const toml::node* where = t.get("look_at") ? t.get("look_at") : t.get("position");
  if (where != nullptr && !follows) {
    const Vec3 view = c.lookAt - c.position;
    if (!(view.norm() > 0)) r.fail(*where, "camera 'look_at' must differ from 'position'");
    if (!(view.normalized().cross(c.up.normalized()).norm() > 1e-9))
      r.fail(*where, "camera 'up' must not be parallel to the view direction (look_at - position)");
  }
  return c;
}

void readCameras(const Reader& r, const toml::table& t, SceneSpec& spec) {
  for (const auto& [k, v] : inFileOrder(t)) {
    const std::string name(k->str());
    const std::string label = "[cameras." + name + "]";
    if (name == "camera")
      r.fail(k->source(), "'camera' names the [camera] table; pick another name");
    spec.cameras.push_back(readCamera(r, r.table(*v, "cameras." + name), name, label, spec));
  }
}

namespace {

// `overlay = ["time", "scale"]`: which overlays are drawn on the frames (any order, none).
void readOverlay(const Reader& r, const toml::node& n, OutputSpec& out) {
  const toml::array* a = n.as_array();
  if (a == nullptr)
    r.fail(n, "'overlay' must be an array of \"time\" and \"scale\", got " + typeName(n));
  const std::vector<std::string> names{"time", "scale"};
  for (std::size_t i = 0; i < a->size(); ++i) {
    const toml::node& item = *a->get(i);
    const std::string name = r.string(item, "overlay[" + std::to_string(i) + "]");
    if (name == "time") {
      out.overlayTime = true;
    } else if (name == "scale") {
      out.overlayScale = true;
    } else {
      std::string message = "unknown overlay '" + name + "'";
      if (auto guess = nearestName(name, names)) message += "; did you mean '" + *guess + "'?";
      r.fail(item, message + " (overlays: time, scale)");
    }
  }
}

}  // namespace

void readOutput(const Reader& r, const toml::table& t, SceneSpec& spec) {
  r.checkKeys(t, sceneKeysOf("output"), "[output]");
  // The size limit is frameSideProblem's; evenness is the MP4 encoder's, so a scene with an odd
  // size still renders PNGs, and an MP4 of it is refused with the message --size would get.
  auto side = [&](const char* key, int& out) {
    if (const auto* n = t.get(key)) {
      const std::int64_t v = r.integer(*n, key);
      const std::string problem = frameSideProblem(key, v);
      if (!problem.empty()) r.fail(*n, problem);
      out = static_cast<int>(v);
    }
  };
  side("width", spec.output.width);
  side("height", spec.output.height);
  if (const auto* n = t.get("crf"))
    spec.output.crf = static_cast<int>(r.integerInRange(*n, "crf", 0, 51));
  if (const auto* n = t.get("speed"))
    spec.output.speed = r.positive(*n, "speed", " (simulated seconds per second of video)");
  if (const auto* n = t.get("alpha")) spec.output.alpha = r.boolean(*n, "alpha");
  if (const auto* n = t.get("overlay")) readOverlay(r, *n, spec.output);
}

// --- [light] ------------------------------------------------------------------------------

// The sun by compass direction and height, or by a date and a UTC time at the terrain's place
// (which the renderer looks up in the DEM's CRS: render/light.cpp); colours in linear RGB.
void readLight(const Reader& r, const toml::table& t, SceneSpec& spec) {
  r.checkKeys(t, sceneKeysOf("light"), "[light]");
  LightSpec& l = spec.light;
  l.where = r.where(t);
  const toml::node* azimuth = t.get("azimuth");
  const toml::node* elevation = t.get("elevation");
  const toml::node* date = t.get("date");
  const toml::node* time = t.get("time");
  if ((azimuth || elevation) && (date || time))
    r.fail(date ? *date : *time,
           "give the sun either by 'azimuth' and 'elevation' or by 'date' and 'time', not both");
  if (azimuth || elevation) {
    if (!azimuth) r.fail(*elevation, "'elevation' needs 'azimuth' too (degrees from north)");
    if (!elevation) r.fail(*azimuth, "'azimuth' needs 'elevation' too (degrees above the horizon)");
    l.azimuthDegrees = r.inRange(*azimuth, "azimuth", -360, 360);
    const double e = r.number(*elevation, "elevation");
    if (!(e > 0 && e <= 90))
      r.fail(*elevation,
             "'elevation' must be above 0 and at most 90 degrees (a sun on or below "
             "the horizon lights nothing), got " +
                 formatNumber(e));
    l.elevationDegrees = e;
  }
  if (date || time) {
    if (!date) r.fail(*time, "'time' needs 'date' too (a TOML date, YYYY-MM-DD)");
    if (!time) r.fail(*date, "'date' needs 'time' too (UTC), e.g. time = 10:30:00");
    const auto* d = date->as_date();
    if (d == nullptr)
      r.fail(*date,
             "'date' must be a TOML date, YYYY-MM-DD without quotes, got " + typeName(*date));
    const auto* clock = time->as_time();
    if (clock == nullptr)
      r.fail(*time, "'time' must be a TOML time of day in UTC such as 10:30:00 (no quotes), got " +
                        typeName(*time));
    const toml::date v = d->get();
    // The solar-position algorithm's range (render/solar_position.h).
    if (v.year < 1800 || v.year > 2200)
      r.fail(*date, "'date' must be in the years 1800 to 2200, got " + std::to_string(v.year));
    l.date = CivilDate{v.year, v.month, v.day};
    const toml::time c = clock->get();
    l.utcSeconds = c.hour * 3600.0 + c.minute * 60.0 + c.second + c.nanosecond * 1e-9;
    if (spec.terrainPath.empty())
      r.fail(*date,
             "'date' and 'time' place the sun for the terrain's location: give [ground] "
             "heightfield (a georeferenced DEM), or the sun's 'azimuth' and 'elevation'");
  }
  if (const auto* n = t.get("intensity")) l.intensity = r.inRange(*n, "intensity", 0, 100);
  if (const auto* n = t.get("color")) l.color = r.color(*n, "color");
  if (const auto* n = t.get("sky")) l.sky = r.color(*n, "sky");
  if (const auto* n = t.get("ambient")) l.ambient = r.color(*n, "ambient");
}

}  // namespace vf::scene_reading

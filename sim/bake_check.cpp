// The checks of a bake's header (bake_format.h): each value against what a scene file may give
// (scene_loader.cpp) or a run writes, so a header edited by hand or damaged gets one error naming
// its key instead of a drawing of nonsense or an allocation that fails.
#include <cmath>
#include <cstdio>
#include <string>
#include <utility>
#include <vector>

#include "sim/bake.h"
#include "sim/bake_format.h"
#include "sim/core/error.h"
#include "sim/shape/sphere_tree.h"

namespace vf {
namespace {

// The rules a header value may break, each throwing an InputError at `where` that names the key,
// the rule and the value.
struct HeaderRules {
  std::string where;

  [[noreturn]] void fail(const std::string& key, const std::string& rule, double got) const {
    char value[64];
    std::snprintf(value, sizeof value, "%.17g", got);
    throw InputError(where, "bad bake header: '" + key + "' " + rule + ", got " + value);
  }
  void positive(const std::string& key, double v) const {
    if (!(std::isfinite(v) && v > 0)) fail(key, "must be a finite number > 0", v);
  }
  void nonNegative(const std::string& key, double v) const {
    if (!(std::isfinite(v) && v >= 0)) fail(key, "must be a finite number >= 0", v);
  }
  void finite(const std::string& key, double v) const {
    if (!std::isfinite(v)) fail(key, "must be finite", v);
  }
  template <class M>  // a vector or matrix
  void finiteAll(const std::string& key, const M& v) const {
    for (const double x : v.reshaped())
      if (!std::isfinite(x)) fail(key, "must hold finite numbers", x);
  }
  void fov(const std::string& key, double v) const {
    if (!(v > 0 && v < 180)) fail(key, "must be in degrees, 0 < fov < 180", v);
  }
};

void checkScene(const HeaderRules& rule, const SceneSpec& s) {
  rule.positive("scene.duration", s.duration);
  rule.positive("scene.fps", s.fps);
  if (s.duration * s.fps > kMaxSceneFrames)
    rule.fail("scene.duration", "times fps must be at most 1e7 frames", s.duration);
  rule.positive("scene.output.speed", s.output.speed);
  if (s.duration * s.fps / s.output.speed > kMaxSceneFrames)
    rule.fail("scene.output.speed", "makes more than 1e7 frames of duration * fps / speed",
              s.output.speed);
  rule.finiteAll("scene.gravity", s.gravity);
  rule.finiteAll("scene.terrain_offset", s.terrainShift);
  if (s.groundPlane) rule.finite("scene.ground_plane", *s.groundPlane);
  for (const auto& [side, pixels] :
       {std::pair{"width", s.output.width}, {"height", s.output.height}})
    if (const std::string problem = frameSideProblem(side, pixels); !problem.empty())
      throw InputError(rule.where, "bad bake header: scene.output: " + problem);
  if (s.output.crf < 0 || s.output.crf > 51)
    rule.fail("scene.output.crf", "must be 0..51", s.output.crf);
}

// The scene's [camera] and named cameras; `bodies`: how many bodies the bake holds.
void checkCameras(const HeaderRules& rule, const SceneSpec& s, int bodies) {
  // Keys are named by their place in the header's JSON.
  std::vector<std::pair<std::string, const CameraSpec*>> cameras{{"scene.camera.", &s.camera}};
  for (std::size_t i = 0; i < s.cameras.size(); ++i)
    cameras.emplace_back("scene.cameras[" + std::to_string(i) + "].", &s.cameras[i]);
  for (const auto& [key, c] : cameras) {
    rule.finiteAll(key + "position", c->position);
    rule.finiteAll(key + "look_at", c->lookAt);
    rule.finiteAll(key + "up", c->up);
    if (!(c->up.norm() > 0)) rule.fail(key + "up", "must be a non-zero vector", 0);
    rule.fov(key + "fov", c->fovDegrees);
    rule.nonNegative(key + "smoothing", c->smoothing);
    rule.nonNegative(key + "min_pixels", c->minPixels);
    rule.nonNegative(key + "trail", c->trailSeconds);
    std::vector<int> followed = c->followGroup;
    if (c->followBody) followed.push_back(*c->followBody);
    for (const int id : followed)
      if (id < 0 || id >= bodies) rule.fail(key + "follow", "must name a body of the bake", id);
    for (const CameraKey& k : c->path) {
      rule.finite(key + "path[].time", k.time);
      rule.finiteAll(key + "path[].position", k.position);
      rule.finiteAll(key + "path[].look_at", k.lookAt);
      rule.fov(key + "path[].fov", k.fovDegrees);
    }
  }
}

void checkLight(const HeaderRules& rule, const LightSpec& light) {
  if (light.azimuthDegrees.has_value() != light.elevationDegrees.has_value())
    rule.fail("scene.light.azimuth", "and 'elevation' must both be numbers or both null", 0);
  if (light.azimuthDegrees) rule.finite("scene.light.azimuth", *light.azimuthDegrees);
  if (light.elevationDegrees && !(*light.elevationDegrees > 0 && *light.elevationDegrees <= 90))
    rule.fail("scene.light.elevation", "must be above 0 and at most 90 degrees",
              *light.elevationDegrees);
  if (light.date && (light.date->month < 1 || light.date->month > 12 || light.date->day < 1 ||
                     light.date->day > 31 || light.date->year < 1800 || light.date->year > 2200))
    rule.fail("scene.light.date", "must be a date [year, month, day] in 1800..2200",
              light.date->year);
  if (!(light.utcSeconds >= 0 && light.utcSeconds < 86400))
    rule.fail("scene.light.utc_seconds", "must be 0 <= s < 86400", light.utcSeconds);
  if (!(light.intensity >= 0 && light.intensity <= 100))
    rule.fail("scene.light.intensity", "must be 0..100", light.intensity);
}

void checkShapes(const HeaderRules& rule, const std::vector<ShapeSpec>& shapes) {
  for (std::size_t i = 0; i < shapes.size(); ++i) {
    const ShapeSpec& shape = shapes[i];
    const std::string key = "shapes[" + std::to_string(i) + "].";
    if (shape.smoothDegrees && !(*shape.smoothDegrees >= 0 && *shape.smoothDegrees <= 180))
      rule.fail(key + "smooth", "must be 0..180 degrees", *shape.smoothDegrees);
    for (int i = 0; i < 3; ++i) rule.positive(key + "scale", shape.scale[i]);
    rule.nonNegative(key + "density", shape.density);  // 0: the scene gave the shape's mass
    if (const auto& r = shape.rock) {
      // Exactly one size, as the scene loader leaves it; the generator asserts as much.
      const int sizes = (r->extents != Vec3::Zero()) + (r->length != 0) + (r->volume != 0);
      if (sizes != 1) rule.fail(key + "rock", "must give one of size, length and volume", sizes);
      if (r->extents != Vec3::Zero())
        for (int k = 0; k < 3; ++k) rule.positive(key + "rock.size", r->extents[k]);
      if (r->length != 0) rule.positive(key + "rock.length", r->length);
      if (r->volume != 0) rule.positive(key + "rock.volume", r->volume);
    }
    const int level = shape.level.value_or(kMinLevel);
    if (level < kMinLevel || level > kMaxLevel)
      rule.fail(key + "level",
                "must be " + std::to_string(kMinLevel) + ".." + std::to_string(kMaxLevel), level);
  }
}

}  // namespace

void checkBakeHeader(const Bake& bake, const std::string& where) {
  const HeaderRules rule{where};
  const SceneSpec& s = bake.scene;
  const int bodies = static_cast<int>(bake.bodies.size());
  checkScene(rule, s);
  checkCameras(rule, s, bodies);
  checkLight(rule, s.light);
  checkShapes(rule, s.shapes);
  for (int i = 0; i < bodies; ++i) {
    const BakeBody& b = bake.bodies[static_cast<std::size_t>(i)];
    const std::string key = "bodies[" + std::to_string(i) + "].";
    rule.nonNegative(key + "inv_mass", b.invMass);
    rule.finiteAll(key + "inertia_body_inv", b.inertiaBodyInv);
  }
}

}  // namespace vf

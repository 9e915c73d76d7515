// [ensemble] and [ensemble.release]: where rocks are released and what is drawn per
// realisation.
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "sim/scene/scene_keys.h"
#include "sim/scene/scene_reader.h"

namespace vf::scene_reading {

// --- [ensemble] ---------------------------------------------------------------------------

namespace {

// `[lo, hi]` with lo <= hi, each within [min, max].
std::array<double, 2> readRange(const Reader& r, const toml::node& n, const std::string& name,
                                double min, double max) {
  const auto v = r.numbers(n, name, 2, "an array of 2 numbers [lo, hi]");
  const toml::array& a = *n.as_array();
  for (std::size_t i = 0; i < 2; ++i)
    if (v[i] < min || v[i] > max)
      r.fail(*a.get(i), "'" + name + "' values must be between " + formatNumber(min) + " and " +
                            formatNumber(max) + ", got " + formatNumber(v[i]));
  if (v[0] > v[1])
    r.fail(n, "'" + name + "' must be [lo, hi] with lo <= hi, got [" + formatNumber(v[0]) + ", " +
                  formatNumber(v[1]) + "]");
  return {v[0], v[1]};
}

// `{ min = [x, y, z], max = [x, y, z] }`, min <= max per component.
void readVectorRange(const Reader& r, const toml::node& n, const std::string& name, Vec3& lo,
                     Vec3& hi) {
  const toml::table& t = r.table(n, name);
  r.checkKeys(t, sceneKeysOf("ensemble." + name), "[ensemble] " + name);
  lo = r.vec3(r.require(t, "min", "[ensemble] " + name), name + ".min");
  hi = r.vec3(r.require(t, "max", "[ensemble] " + name), name + ".max");
  for (int i = 0; i < 3; ++i)
    if (lo[i] > hi[i])
      r.fail(*t.get("max"), "'" + name + ".max' must be >= '" + name + ".min' in every component");
}

void readRelease(const Reader& r, const toml::table& t, const fs::path& sceneFolder,
                 EnsembleSpec& e) {
  r.checkKeys(t, sceneKeysOf("ensemble.release"), "[ensemble.release]");
  const char* const kinds[] = {"area", "line", "points", "cells"};
  const toml::node* given = nullptr;
  std::string key;
  for (const char* k : kinds) {
    if (const auto* n = t.get(k)) {
      if (given != nullptr)
        r.fail(*n,
               "give one of 'area', 'line', 'points' or 'cells' in [ensemble.release], not "
               "both '" +
                   key + "' and '" + k + "'");
      given = n;
      key = k;
    }
  }
  if (given == nullptr)
    r.fail(t,
           "[ensemble.release] needs one of 'area' (polygon [[x, y], ...]), 'line' "
           "([[x, y], ...]), 'points' ([[x, y], ...]) or 'cells' (a source raster)");
  e.releaseKey = "release." + key;
  e.releaseWhere = r.where(*given);
  if (key == "cells") {
    e.release = ReleaseKind::kCells;
    e.cellsPath = existingFile(r, *given, e.releaseKey, sceneFolder, "source raster");
    return;
  }
  e.release = key == "area"   ? ReleaseKind::kArea
              : key == "line" ? ReleaseKind::kLine
                              : ReleaseKind::kPoints;
  const std::size_t least = key == "area" ? 3 : key == "line" ? 2 : 1;
  const toml::array* a = given->as_array();
  if (a == nullptr || a->size() < least)
    r.fail(*given,
           "'" + e.releaseKey + "' must be an array of at least " + std::to_string(least) +
               " [x, y] points (world coordinates, m), got " +
               (a == nullptr ? typeName(*given) : "an array of " + std::to_string(a->size())));
  for (std::size_t i = 0; i < a->size(); ++i) {
    const std::string name = e.releaseKey + "[" + std::to_string(i) + "]";
    const auto v = r.numbers(*a->get(i), name, 2, "an array of 2 numbers [x, y]");
    e.releasePoints.push_back({v[0], v[1]});
    e.releasePointWhere.push_back(r.where(*a->get(i)));
  }
  if (e.release == ReleaseKind::kArea) {
    double twiceArea = 0;  // shoelace
    for (std::size_t i = 0; i < e.releasePoints.size(); ++i) {
      const Point2& p = e.releasePoints[i];
      const Point2& q = e.releasePoints[(i + 1) % e.releasePoints.size()];
      twiceArea += p[0] * q[1] - q[0] * p[1];
    }
    if (!(std::abs(twiceArea) > 0)) r.fail(*given, "'release.area' encloses no area");
  }
  if (e.release == ReleaseKind::kLine) {
    double length = 0;
    for (std::size_t i = 1; i < e.releasePoints.size(); ++i)
      length += std::hypot(e.releasePoints[i][0] - e.releasePoints[i - 1][0],
                           e.releasePoints[i][1] - e.releasePoints[i - 1][1]);
    if (!(length > 0)) r.fail(*given, "'release.line' has zero length");
  }
}

}  // namespace

void readEnsemble(const Reader& r, const toml::table& t, const fs::path& sceneFolder,
                  SceneSpec& spec) {
  r.checkKeys(t, sceneKeysOf("ensemble"), "[ensemble]");
  EnsembleSpec e;
  e.where = r.where(t);
  if (const auto* n = t.get("seed")) {
    const std::int64_t seed = r.integer(*n, "seed");
    if (seed < 0) r.fail(*n, "'seed' must be an integer >= 0, got " + std::to_string(seed));
    e.seed = static_cast<std::uint64_t>(seed);
  }
  const toml::node* one = t.get("shape");
  const toml::node* many = t.get("shapes");
  if (one != nullptr && many != nullptr)
    r.fail(*many, "give either 'shape' or 'shapes' in [ensemble], not both");
  const auto names = shapeNames(spec);
  // An entry names a shape, or a rock family: all its variants, equally likely.
  auto shapeEntry = [&](const toml::node& n, const std::string& key) {
    const std::string name = r.string(n, key);
    if (isShapeName(spec, name)) return std::vector<std::string>{name};
    if (auto members = familyMembers(spec, name); !members.empty()) return members;
    std::string message = "unknown shape '" + name + "'";
    if (auto guess = nearestName(name, names))
      message += "; did you mean '" + *guess + "'?";
    else
      message += "; defined shapes: " + (names.empty() ? std::string("none") : joinNames(names));
    r.fail(n, message);
  };
  std::vector<std::vector<std::string>> entries;
  if (one != nullptr) {
    entries.push_back(shapeEntry(*one, "shape"));
  } else if (many != nullptr) {
    const toml::array* a = many->as_array();
    if (a == nullptr || a->empty())
      r.fail(*many, "'shapes' must be a non-empty array of shape names, got " +
                        (a == nullptr ? typeName(*many) : std::string("an empty array")));
    for (std::size_t i = 0; i < a->size(); ++i)
      entries.push_back(shapeEntry(*a->get(i), "shapes[" + std::to_string(i) + "]"));
  } else {
    r.fail(t, "missing required key 'shape' (or 'shapes', drawn with 'weights') in [ensemble]");
  }
  std::vector<double> entryWeights(entries.size(), 1.0);
  if (const auto* n = t.get("weights")) {
    const toml::array* a = n->as_array();
    if (a == nullptr || a->size() != entries.size())
      r.fail(*n, "'weights' must be an array of " + std::to_string(entries.size()) +
                     " numbers, one per entry of 'shapes'");
    for (std::size_t i = 0; i < a->size(); ++i)
      entryWeights[i] = r.positive(*a->get(i), "weights[" + std::to_string(i) + "]", "");
  }
  // A family's weight is shared equally by its variants.
  for (std::size_t i = 0; i < entries.size(); ++i)
    for (const std::string& name : entries[i]) {
      e.shapes.push_back(name);
      e.weights.push_back(entryWeights[i] / static_cast<double>(entries[i].size()));
    }
  readRelease(r, r.table(r.require(t, "release", "[ensemble]"), "release"), sceneFolder, e);
  if (const auto* n = t.get("drop_height"))
    e.dropHeight = r.nonNegative(*n, "drop_height", " m (lowest point above the surface)");
  if (const auto* n = t.get("orientation")) {
    const std::string v = r.string(*n, "orientation");
    if (v != "random" && v != "fixed")
      r.fail(*n,
             "'orientation' must be \"random\" (uniform over all rotations, the default) "
             "or \"fixed\" (the mesh file's axes), got \"" +
                 v + "\"");
    e.randomOrientation = v == "random";
  }
  if (const auto* n = t.get("velocity"))
    readVectorRange(r, *n, "velocity", e.velocityMin, e.velocityMax);
  if (const auto* n = t.get("angular_velocity"))
    readVectorRange(r, *n, "angular_velocity", e.angularVelocityMin, e.angularVelocityMax);
  if (const auto* n = t.get("restitution")) e.restitution = readRange(r, *n, "restitution", 0, 1);
  if (const auto* n = t.get("friction")) e.friction = readRange(r, *n, "friction", 0, 100);
  if (const auto* n = t.get("rolling_resistance")) {
    if (spec.groundMaterial.empty())
      r.fail(*n, "'rolling_resistance' varies the ground material's; give [ground] material");
    e.rollingResistance = readRange(r, *n, "rolling_resistance", 0, 100);
  }
  if (spec.terrainPath.empty())
    r.fail(t, "[ensemble] needs terrain: statistics are per cell of [ground] heightfield");
  spec.ensemble = std::move(e);
}

}  // namespace vf::scene_reading

// [ensemble] and [ensemble.release]: where rocks are released (one source or several, drawn by
// weight) and what is drawn per realisation.
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

// `[a, b, ...]`: 1 to kMaxClassLimits class limits, each > 0, strictly ascending.
constexpr std::size_t kMaxClassLimits = 5;
std::vector<double> readClassLimits(const Reader& r, const toml::node& n, const std::string& name,
                                    const std::string& units) {
  const toml::array* a = n.as_array();
  const std::string what =
      "an array of 1 to " + std::to_string(kMaxClassLimits) + " ascending limits in " + units;
  if (a == nullptr || a->empty() || a->size() > kMaxClassLimits)
    r.fail(n, "'" + name + "' must be " + what);
  std::vector<double> limits;
  for (std::size_t i = 0; i < a->size(); ++i) {
    const std::string item = name + "[" + std::to_string(i) + "]";
    limits.push_back(r.positive(*a->get(i), item, " " + units));
    if (i > 0 && limits[i] <= limits[i - 1])
      r.fail(*a->get(i), "'" + name + "' must be ascending, got " + formatNumber(limits[i]) +
                             " after " + formatNumber(limits[i - 1]));
  }
  return limits;
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

// `volume = { distribution = "lognormal", median, sigma, min, max }` or
// `{ distribution = "power", exponent, min, max }` (m^3); `name` is "volume" or
// "release[i].volume".
VolumeSpec readVolume(const Reader& r, const toml::node& node, const std::string& name) {
  const toml::table& t = r.table(node, name);
  r.checkKeys(t, sceneKeysOf("ensemble.volume"), "'" + name + "'");
  VolumeSpec v;
  v.where = r.where(t);
  const toml::node& law = r.require(t, "distribution", "'" + name + "'");
  const std::string kind = r.string(law, name + ".distribution");
  if (kind != "lognormal" && kind != "power")
    r.fail(law,
           "'" + name + ".distribution' must be \"lognormal\" or \"power\", got \"" + kind + "\"");
  v.law = kind == "power" ? VolumeSpec::Law::kPower : VolumeSpec::Law::kLogNormal;
  const auto need = [&](const char* key) -> const toml::node& {
    return r.require(t, key, "'" + name + "' (distribution = \"" + kind + "\")");
  };
  const auto refuse = [&](const char* key) {
    if (const auto* n = t.get(key))
      r.fail(*n, "'" + name + "." + key + "' does not belong to distribution \"" + kind + "\"");
  };
  if (v.law == VolumeSpec::Law::kLogNormal) {
    refuse("exponent");
    v.median = r.positive(need("median"), name + ".median", " m^3");
    v.sigma = r.positive(need("sigma"), name + ".sigma", "");
  } else {
    refuse("median");
    refuse("sigma");
    v.exponent = r.positive(need("exponent"), name + ".exponent", "");
  }
  v.min = r.positive(need("min"), name + ".min", " m^3");
  const toml::node& maxNode = need("max");
  v.max = r.positive(maxNode, name + ".max", " m^3");
  if (!(v.max > v.min))
    r.fail(maxNode, "'" + name + ".max' must be > '" + name + ".min' (" + formatNumber(v.min) +
                        " m^3), got " + formatNumber(v.max));
  return v;
}

// The one form a release source gives: exactly one of area, line, points, cells or file.
const toml::node& releaseForm(const Reader& r, const toml::table& t, const std::string& label,
                              std::string& form) {
  const char* const kinds[] = {"area", "line", "points", "cells", "file"};
  const toml::node* given = nullptr;
  for (const char* k : kinds) {
    if (const auto* n = t.get(k)) {
      if (given != nullptr)
        r.fail(*n, "give one of 'area', 'line', 'points', 'cells' or 'file' in " + label +
                       ", not both '" + form + "' and '" + k + "'");
      given = n;
      form = k;
    }
  }
  if (given == nullptr)
    r.fail(t, label +
                  " needs one of 'area' (polygon [[x, y], ...]), 'line' ([[x, y], ...]), "
                  "'points' ([[x, y], ...]), 'cells' (a source raster) or 'file' (a vector "
                  "file: GeoPackage, Shapefile, GeoJSON)");
  return *given;
}

// The vertices of an area, line or points form, in the DEM's coordinates.
void readReleasePoints(const Reader& r, const toml::node& given, ReleaseSpec& s) {
  const std::size_t least = s.kind == ReleaseKind::kArea ? 3 : s.kind == ReleaseKind::kLine ? 2 : 1;
  const toml::array* a = given.as_array();
  if (a == nullptr || a->size() < least)
    r.fail(given,
           "'" + s.key + "' must be an array of at least " + std::to_string(least) +
               " [x, y] points (the DEM's coordinates, m), got " +
               (a == nullptr ? typeName(given) : "an array of " + std::to_string(a->size())));
  for (std::size_t i = 0; i < a->size(); ++i) {
    const std::string name = s.key + "[" + std::to_string(i) + "]";
    const auto v = r.numbers(*a->get(i), name, 2, "an array of 2 numbers [x, y]");
    s.points.push_back({v[0], v[1]});
    s.pointWhere.push_back(r.where(*a->get(i)));
  }
  if (s.kind == ReleaseKind::kArea) {
    double twiceArea = 0;  // shoelace
    for (std::size_t i = 0; i < s.points.size(); ++i) {
      const Point2& p = s.points[i];
      const Point2& q = s.points[(i + 1) % s.points.size()];
      twiceArea += p[0] * q[1] - q[0] * p[1];
    }
    if (!(std::abs(twiceArea) > 0)) r.fail(given, "'" + s.key + "' encloses no area");
  }
  if (s.kind == ReleaseKind::kLine) {
    double length = 0;
    for (std::size_t i = 1; i < s.points.size(); ++i)
      length +=
          std::hypot(s.points[i][0] - s.points[i - 1][0], s.points[i][1] - s.points[i - 1][1]);
    if (!(length > 0)) r.fail(given, "'" + s.key + "' has zero length");
  }
}

// One source; `prefix` is "release" for a single table, "release[i]" in an array of them.
ReleaseSpec readReleaseSource(const Reader& r, const toml::table& t, const fs::path& sceneFolder,
                              const std::string& prefix) {
  const std::string label = "[ensemble." + prefix + "]";
  r.checkKeys(t, sceneKeysOf("ensemble.release"), label);
  ReleaseSpec s;
  std::string form;
  const toml::node& given = releaseForm(r, t, label, form);
  s.key = prefix + "." + form;
  s.where = r.where(given);
  if (const auto* n = t.get("weight")) s.weight = r.positive(*n, prefix + ".weight", "");
  if (const auto* n = t.get("volume")) s.volume = readVolume(r, *n, prefix + ".volume");
  const bool fromFile = form == "file";
  for (const char* k : {"layer", "weight_field"})
    if (const auto* n = t.get(k); n != nullptr && !fromFile)
      r.fail(*n, "'" + prefix + "." + k + "' belongs to a 'file' source, not to '" + s.key + "'");
  if (form == "cells") {
    s.kind = ReleaseKind::kCells;
    s.path = existingFile(r, given, s.key, sceneFolder, "source raster");
  } else if (fromFile) {
    s.kind = ReleaseKind::kFile;
    s.path = existingFile(r, given, s.key, sceneFolder, "release vector file");
    if (const auto* n = t.get("layer")) s.layer = r.string(*n, prefix + ".layer");
    if (const auto* n = t.get("weight_field"))
      s.weightField = r.string(*n, prefix + ".weight_field");
  } else {
    s.kind = form == "area"   ? ReleaseKind::kArea
             : form == "line" ? ReleaseKind::kLine
                              : ReleaseKind::kPoints;
    readReleasePoints(r, given, s);
  }
  return s;
}

// `release = { ... }` (one source) or `[[ensemble.release]]` tables (several, each drawn with
// its `weight`).
void readRelease(const Reader& r, const toml::node& n, const fs::path& sceneFolder,
                 EnsembleSpec& e) {
  if (const toml::array* a = n.as_array()) {
    if (a->empty() || !a->is_array_of_tables())
      r.fail(n,
             "'release' must be a table ({ area = ... }) or release tables ([[ensemble.release]]), "
             "got " +
                 (a->empty() ? std::string("an empty array") : std::string("an array")));
    for (std::size_t i = 0; i < a->size(); ++i)
      e.releases.push_back(readReleaseSource(r, *a->get(i)->as_table(), sceneFolder,
                                             "release[" + std::to_string(i) + "]"));
    return;
  }
  e.releases.push_back(readReleaseSource(r, r.table(n, "release"), sceneFolder, "release"));
}

// An entry of 'shape' or 'shapes' names a shape, or a rock family: all its variants, equally
// likely. `names` are the scene's shapes, for the message.
std::vector<std::string> shapeEntry(const Reader& r, const SceneSpec& spec,
                                    const std::vector<std::string>& names, const toml::node& n,
                                    const std::string& key) {
  const std::string name = r.string(n, key);
  if (isShapeName(spec, name)) return std::vector<std::string>{name};
  if (auto members = familyMembers(spec, name); !members.empty()) return members;
  std::string message = "unknown shape '" + name + "'";
  if (auto guess = nearestName(name, names))
    message += "; did you mean '" + *guess + "'?";
  else
    message += "; defined shapes: " + (names.empty() ? std::string("none") : joinNames(names));
  r.fail(n, message);
}

// 'shape' or 'shapes': the entries drawn from, each a list of shape names.
std::vector<std::vector<std::string>> readShapeEntries(const Reader& r, const toml::table& t,
                                                       const SceneSpec& spec) {
  const toml::node* one = t.get("shape");
  const toml::node* many = t.get("shapes");
  if (one != nullptr && many != nullptr)
    r.fail(*many, "give either 'shape' or 'shapes' in [ensemble], not both");
  const auto names = shapeNames(spec);
  std::vector<std::vector<std::string>> entries;
  if (one != nullptr) {
    entries.push_back(shapeEntry(r, spec, names, *one, "shape"));
  } else if (many != nullptr) {
    const toml::array* a = many->as_array();
    if (a == nullptr || a->empty())
      r.fail(*many, "'shapes' must be a non-empty array of shape names, got " +
                        (a == nullptr ? typeName(*many) : std::string("an empty array")));
    for (std::size_t i = 0; i < a->size(); ++i)
      entries.push_back(
          shapeEntry(r, spec, names, *a->get(i), "shapes[" + std::to_string(i) + "]"));
  } else {
    r.fail(t, "missing required key 'shape' (or 'shapes', drawn with 'weights') in [ensemble]");
  }
  return entries;
}

// The shapes and their weights from the entries and 'weights' (1 each without it); a family's
// weight is shared equally by its variants.
void readShapeWeights(const Reader& r, const toml::table& t,
                      const std::vector<std::vector<std::string>>& entries, EnsembleSpec& e) {
  std::vector<double> entryWeights(entries.size(), 1.0);
  if (const auto* n = t.get("weights")) {
    const toml::array* a = n->as_array();
    if (a == nullptr || a->size() != entries.size())
      r.fail(*n, "'weights' must be an array of " + std::to_string(entries.size()) +
                     " numbers, one per entry of 'shapes'");
    for (std::size_t i = 0; i < a->size(); ++i)
      entryWeights[i] = r.positive(*a->get(i), "weights[" + std::to_string(i) + "]", "");
  }
  for (std::size_t i = 0; i < entries.size(); ++i)
    for (const std::string& name : entries[i]) {
      e.shapes.push_back(name);
      e.weights.push_back(entryWeights[i] / static_cast<double>(entries[i].size()));
    }
}

// 'orientation': "random" or "fixed".
bool readRandomOrientation(const Reader& r, const toml::node& n) {
  const std::string v = r.string(n, "orientation");
  if (v != "random" && v != "fixed")
    r.fail(n,
           "'orientation' must be \"random\" (uniform over all rotations, the default) "
           "or \"fixed\" (the mesh file's axes), got \"" +
               v + "\"");
  return v == "random";
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
  readShapeWeights(r, t, readShapeEntries(r, t, spec), e);
  readRelease(r, r.require(t, "release", "[ensemble]"), sceneFolder, e);
  if (const auto* n = t.get("drop_height"))
    e.dropHeight = r.nonNegative(*n, "drop_height", " m (lowest point above the surface)");
  if (const auto* n = t.get("orientation")) e.randomOrientation = readRandomOrientation(r, *n);
  if (const auto* n = t.get("velocity"))
    readVectorRange(r, *n, "velocity", e.velocityMin, e.velocityMax);
  if (const auto* n = t.get("angular_velocity"))
    readVectorRange(r, *n, "angular_velocity", e.angularVelocityMin, e.angularVelocityMax);
  if (const auto* n = t.get("restitution")) e.restitution = readRange(r, *n, "restitution", 0, 1);
  if (const auto* n = t.get("friction")) e.friction = readRange(r, *n, "friction", 0, 100);
  if (const auto* n = t.get("volume")) e.volume = readVolume(r, *n, "volume");
  if (const auto* n = t.get("density")) e.density = readRange(r, *n, "density", 1, 1e5);
  if (const auto* n = t.get("height_classes"))
    e.heightClasses = readClassLimits(r, *n, "height_classes", "m");
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

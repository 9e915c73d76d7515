// Scene files (TOML) -> SceneSpec. The only file in voxfall that includes toml++.
//
// Every value goes through a Reader that knows the file name, so each problem becomes one
// InputError at "file:line:column" of the offending key or value, saying what is wrong and what
// would be valid. Unknown keys are errors, never ignored: a typo such as `restitutoin` must not
// silently fall back to a default, so the nearest valid key is suggested by edit distance.
// Errors are reported in file order within a table, so the first problem a reader would meet is
// the one shown.
#include <toml++/toml.h>

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "sim/core/error.h"
#include "sim/ground/ground_material.h"
#include "sim/scene/scene.h"
#include "sim/scene/scene_keys.h"
#include "sim/shape/crs.h"
#include "sim/shape/sphere_tree.h"

namespace vf {
namespace {

namespace fs = std::filesystem;

// Guards against values that parse but cannot be run (allocation of body arrays; frames:
// kMaxSceneFrames).
constexpr std::int64_t kMaxEmitterCount = 1000000;

std::string lower(std::string_view s) {
  std::string out(s);
  for (char& c : out) {
    if (c >= 'A' && c <= 'Z') c = static_cast<char>(c - 'A' + 'a');
  }
  return out;
}

// Optimal string alignment distance (Levenshtein plus adjacent transpositions): swapping two
// neighbouring letters, the commonest typo ("restitutoin"), counts as one edit, not two.
int editDistance(std::string_view a, std::string_view b) {
  const std::size_t n = a.size(), m = b.size();
  std::vector<std::vector<int>> d(n + 1, std::vector<int>(m + 1, 0));
  for (std::size_t i = 0; i <= n; ++i) d[i][0] = static_cast<int>(i);
  for (std::size_t j = 0; j <= m; ++j) d[0][j] = static_cast<int>(j);
  for (std::size_t i = 1; i <= n; ++i) {
    for (std::size_t j = 1; j <= m; ++j) {
      const int cost = a[i - 1] == b[j - 1] ? 0 : 1;
      d[i][j] = std::min({d[i - 1][j] + 1, d[i][j - 1] + 1, d[i - 1][j - 1] + cost});
      if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1])
        d[i][j] = std::min(d[i][j], d[i - 2][j - 2] + 1);
    }
  }
  return d[n][m];
}

// The candidate a user most plausibly meant by `word`, or nothing when none is close: a wrong
// suggestion is worse than the list of valid names. Ties go to the earlier candidate, so the
// suggestion does not depend on anything but the lists' order.
std::optional<std::string> nearestName(std::string_view word,
                                       const std::vector<std::string>& candidates) {
  const std::string w = lower(word);
  std::optional<std::string> best;
  int bestDistance = std::numeric_limits<int>::max();
  for (const std::string& c : candidates) {
    const int d = editDistance(w, lower(c));
    if (d < bestDistance) {
      bestDistance = d;
      best = c;
    }
  }
  if (best && bestDistance <= std::max<int>(1, static_cast<int>(best->size()) / 3)) return best;
  // An abbreviation ("pos" for "position") is plausible even when many letters are missing.
  if (w.size() >= 3) {
    for (const std::string& c : candidates) {
      if (lower(c).starts_with(w)) return c;
    }
  }
  return std::nullopt;
}

std::string joinNames(const std::vector<std::string>& names) {
  std::string s;
  for (std::size_t i = 0; i < names.size(); ++i) {
    if (i > 0) s += ", ";
    s += names[i];
  }
  return s;
}

std::string formatNumber(double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.6g", v);
  return buf;
}

std::string typeName(const toml::node& n) {
  switch (n.type()) {
    case toml::node_type::table:
      return "table";
    case toml::node_type::array:
      return "array";
    case toml::node_type::string:
      return "string";
    case toml::node_type::integer:
      return "integer";
    case toml::node_type::floating_point:
      return "float";
    case toml::node_type::boolean:
      return "boolean";
    case toml::node_type::date:
      return "date";
    case toml::node_type::time:
      return "time";
    case toml::node_type::date_time:
      return "date-time";
    default:
      return "nothing";
  }
}

bool before(const toml::source_region& a, const toml::source_region& b) {
  if (a.begin.line != b.begin.line) return a.begin.line < b.begin.line;
  return a.begin.column < b.begin.column;
}

// Reads typed, validated values out of the parsed document; every failure throws InputError at
// the node's position. `name` is the key as the user wrote it ("duration", "jitter.seed").
class Reader {
 public:
  explicit Reader(std::string file) : file_(std::move(file)) {}

  std::string where(const toml::source_region& r) const {
    return sourceLocation(file_, static_cast<int>(r.begin.line), static_cast<int>(r.begin.column));
  }
  std::string where(const toml::node& n) const { return where(n.source()); }

  [[noreturn]] void fail(const toml::node& n, const std::string& message) const {
    throw InputError(where(n), message);
  }
  [[noreturn]] void fail(const toml::source_region& r, const std::string& message) const {
    throw InputError(where(r), message);
  }

  // Rejects any key of `t` not in `valid`, reporting the first one in file order.
  void checkKeys(const toml::table& t, const std::vector<std::string>& valid,
                 const std::string& tableLabel) const {
    const toml::key* first = nullptr;
    for (auto&& [k, v] : t) {
      (void)v;
      if (std::find(valid.begin(), valid.end(), k.str()) != valid.end()) continue;
      if (first == nullptr || before(k.source(), first->source())) first = &k;
    }
    if (first == nullptr) return;
    std::string message = "unknown key '" + std::string(first->str()) + "' in " + tableLabel;
    if (auto guess = nearestName(first->str(), valid))
      message += "; did you mean '" + *guess + "'?";
    else
      message += "; valid keys: " + joinNames(valid);
    fail(first->source(), message);
  }

  // A required sub-table or key: missing ones are reported at the enclosing table.
  const toml::node& require(const toml::table& t, std::string_view key,
                            const std::string& tableLabel) const {
    const toml::node* n = t.get(key);
    if (n == nullptr) fail(t, "missing required key '" + std::string(key) + "' in " + tableLabel);
    return *n;
  }

  const toml::table& table(const toml::node& n, const std::string& name) const {
    const toml::table* t = n.as_table();
    if (t == nullptr) fail(n, "'" + name + "' must be a table, got " + typeName(n));
    return *t;
  }

  double number(const toml::node& n, const std::string& name) const {
    double v = 0;
    if (const auto* i = n.as_integer())
      v = static_cast<double>(i->get());  // integers are fine where numbers are expected
    else if (const auto* f = n.as_floating_point())
      v = f->get();
    else
      fail(n, "'" + name + "' must be a number, got " + typeName(n));
    if (!std::isfinite(v))
      fail(n, "'" + name + "' must be a finite number, got " + formatNumber(v));
    return v;
  }

  double positive(const toml::node& n, const std::string& name, const std::string& unit) const {
    const double v = number(n, name);
    if (!(v > 0)) fail(n, "'" + name + "' must be > 0" + unit + ", got " + formatNumber(v));
    return v;
  }

  double nonNegative(const toml::node& n, const std::string& name, const std::string& unit) const {
    const double v = number(n, name);
    if (v < 0) fail(n, "'" + name + "' must be >= 0" + unit + ", got " + formatNumber(v));
    return v;
  }

  double inRange(const toml::node& n, const std::string& name, double lo, double hi) const {
    const double v = number(n, name);
    if (v < lo || v > hi)
      fail(n, "'" + name + "' must be between " + formatNumber(lo) + " and " + formatNumber(hi) +
                  ", got " + formatNumber(v));
    return v;
  }

  std::int64_t integer(const toml::node& n, const std::string& name) const {
    const auto* i = n.as_integer();
    if (i == nullptr) fail(n, "'" + name + "' must be an integer, got " + typeName(n));
    return i->get();
  }

  std::int64_t integerInRange(const toml::node& n, const std::string& name, std::int64_t lo,
                              std::int64_t hi) const {
    const std::int64_t v = integer(n, name);
    if (v < lo || v > hi)
      fail(n, "'" + name + "' must be an integer from " + std::to_string(lo) + " to " +
                  std::to_string(hi) + ", got " + std::to_string(v));
    return v;
  }

  bool boolean(const toml::node& n, const std::string& name) const {
    const auto* b = n.as_boolean();
    if (b == nullptr) fail(n, "'" + name + "' must be true or false, got " + typeName(n));
    return b->get();
  }

  std::string string(const toml::node& n, const std::string& name) const {
    const auto* s = n.as_string();
    if (s == nullptr) fail(n, "'" + name + "' must be a string, got " + typeName(n));
    return s->get();
  }

  // An array of exactly `size` numbers.
  std::vector<double> numbers(const toml::node& n, const std::string& name, std::size_t size,
                              const std::string& what) const {
    const toml::array* a = n.as_array();
    if (a == nullptr) fail(n, "'" + name + "' must be " + what + ", got " + typeName(n));
    if (a->size() != size)
      fail(n, "'" + name + "' must be " + what + ", got an array of " + std::to_string(a->size()));
    std::vector<double> out;
    for (std::size_t i = 0; i < size; ++i)
      out.push_back(number(*a->get(i), name + "[" + std::to_string(i) + "]"));
    return out;
  }

  Vec3 vec3(const toml::node& n, const std::string& name) const {
    const auto v = numbers(n, name, 3, "an array of 3 numbers [x, y, z]");
    return Vec3(v[0], v[1], v[2]);
  }

  Color color(const toml::node& n, const std::string& name) const {
    const auto v = numbers(n, name, 3, "an array of 3 numbers [r, g, b] (linear RGB, 0..1)");
    const toml::array& a = *n.as_array();
    Color c{};
    for (std::size_t i = 0; i < 3; ++i) {
      if (v[i] < 0 || v[i] > 1)
        fail(*a.get(i), "'" + name + "' components must be between 0 and 1 (linear RGB), got " +
                            formatNumber(v[i]));
      c[i] = static_cast<float>(v[i]);
    }
    return c;
  }

  // File order w, x, y, z; normalised, since nobody writes unit quaternions by hand exactly.
  Quat quaternion(const toml::node& n, const std::string& name) const {
    const auto v = numbers(n, name, 4, "an array of 4 numbers [w, x, y, z]");
    Quat q(v[0], v[1], v[2], v[3]);
    const double norm = q.norm();
    if (!(norm > 1e-12) || !std::isfinite(norm))
      fail(n, "'" + name +
                  "' must be a non-zero quaternion [w, x, y, z] (it is normalised; "
                  "[1, 0, 0, 0] is no rotation), got a zero quaternion");
    q.coeffs() /= norm;
    return q;
  }

 private:
  std::string file_;
};

// --- [simulation] -------------------------------------------------------------------------

void readSimulation(const Reader& r, const toml::table& t, SceneSpec& spec) {
  r.checkKeys(t, sceneKeysOf("simulation"), "[simulation]");
  if (const auto* n = t.get("rotation")) {
    const std::string v = r.string(*n, "rotation");
    if (v != "euler" && v != "midpoint")
      r.fail(*n,
             "'rotation' must be \"euler\" (the paper's explicit Euler) or \"midpoint\" (keeps "
             "the energy of free tumbling; the default with ground materials), got \"" +
                 v + "\"");
    spec.rotation = v == "midpoint" ? RotationUpdate::kMidpoint : RotationUpdate::kExplicitEuler;
  }
  if (const auto* n = t.get("stop")) {
    const std::string v = r.string(*n, "stop");
    if (v != "duration" && v != "all_at_rest")
      r.fail(*n,
             "'stop' must be \"duration\" (the default) or \"all_at_rest\" (every rock "
             "stopped or gone), got \"" +
                 v + "\"");
    spec.stopWhenSettled = v == "all_at_rest";
  }
  if (const auto* n = t.get("rest")) {
    const toml::table& rt = r.table(*n, "rest");
    r.checkKeys(rt, sceneKeysOf("simulation.rest"), "[simulation] rest");
    if (const auto* x = rt.get("speed")) spec.rest.speed = r.positive(*x, "rest.speed", " m/s");
    if (const auto* x = rt.get("time")) spec.rest.time = r.nonNegative(*x, "rest.time", " s");
  }
  if (const auto* n = t.get("duration")) spec.duration = r.positive(*n, "duration", " s");
  if (const auto* n = t.get("level"))
    spec.level = static_cast<int>(r.integerInRange(*n, "level", kMinLevel, kMaxLevel));
  if (const auto* n = t.get("step")) {
    const std::string valid = "'step' must be " + stepRuleChoices();
    if (const auto* s = n->as_string()) {  // the text --step takes
      const auto rule = parseStepRule(s->get());
      if (!rule) r.fail(*n, valid + ", got \"" + s->get() + "\"");
      spec.step = *rule;
    } else if (n->is_number()) {
      const double v = r.number(*n, "step");
      if (!(v > 0)) r.fail(*n, valid + ", got " + formatNumber(v));
      spec.step = StepRule::fixed(v);
    } else {
      r.fail(*n, valid + ", got " + typeName(*n));
    }
  }
  if (const auto* n = t.get("gravity")) spec.gravity = r.vec3(*n, "gravity");
  if (const auto* n = t.get("fps")) spec.fps = r.positive(*n, "fps", " frames per second");
  if (const auto* n = t.get("collider")) {
    const std::string c = r.string(*n, "collider");
    if (c == "voxel")
      spec.collider = ColliderMethod::kVoxel;
    else if (c == "polygon")
      spec.collider = ColliderMethod::kPolygon;
    else
      r.fail(*n,
             "'collider' must be \"voxel\" (sphere trees) or \"polygon\" (the paper's "
             "comparison method, convex meshes only), got \"" +
                 c + "\"");
  }
  if (const auto* n = t.get("method")) {
    const std::string m = r.string(*n, "method");
    if (m != "fast" && m != "paper")
      r.fail(*n,
             "'method' must be \"fast\" (contact reduction and sleeping, the default) or "
             "\"paper\" (the paper's method: neither), got \"" +
                 m + "\"");
    spec.contactReduction = spec.sleep = m == "fast";
  }
  // Each key overrides the method's choice.
  if (const auto* n = t.get("contact_reduction"))
    spec.contactReduction = r.boolean(*n, "contact_reduction");
  if (const auto* n = t.get("sleep")) spec.sleep = r.boolean(*n, "sleep");
  // Runaway limits (sim/run_guard.h).
  if (const auto* n = t.get("max_steps"))
    spec.limits.maxSteps = static_cast<std::uint64_t>(
        r.integerInRange(*n, "max_steps", 1, std::numeric_limits<std::int64_t>::max()));
  if (const auto* n = t.get("max_speed"))
    spec.limits.maxSpeed = r.positive(*n, "max_speed", " m/s");
}

// --- [contact] ----------------------------------------------------------------------------

void readContact(const Reader& r, const toml::table& t, ContactMaterial& c) {
  r.checkKeys(t, sceneKeysOf("contact"), "[contact]");
  if (const auto* n = t.get("restitution")) {
    const toml::table& e = r.table(*n, "restitution");
    r.checkKeys(e, sceneKeysOf("contact.restitution"), "[contact] restitution");
    if (const auto* v = e.get("body_body"))
      c.restitutionBodyBody = r.inRange(*v, "restitution.body_body", 0, 1);
    if (const auto* v = e.get("body_ground"))
      c.restitutionBodyGround = r.inRange(*v, "restitution.body_ground", 0, 1);
  }
  if (const auto* n = t.get("friction")) {
    const toml::table& f = r.table(*n, "friction");
    r.checkKeys(f, sceneKeysOf("contact.friction"), "[contact] friction");
    if (const auto* v = f.get("body_body"))
      c.frictionBodyBody = r.nonNegative(*v, "friction.body_body", " (Coulomb coefficient)");
    if (const auto* v = f.get("body_ground"))
      c.frictionBodyGround = r.nonNegative(*v, "friction.body_ground", " (Coulomb coefficient)");
  }
}

// --- [ground] -----------------------------------------------------------------------------

// The path in string `n` (key `key`), resolved against the scene's folder; it must name a file,
// else the error says "WHAT not found: 'PATH'" and then `hint`.
std::string existingFile(const Reader& r, const toml::node& n, const std::string& key,
                         const fs::path& sceneFolder, const std::string& what,
                         const std::string& hint = "") {
  fs::path resolved(r.string(n, key));
  if (resolved.is_relative()) resolved = sceneFolder / resolved;
  resolved = resolved.lexically_normal();
  std::error_code ec;
  if (!fs::is_regular_file(resolved, ec))
    r.fail(n, what + " not found: '" + resolved.string() + "'" + hint);
  return resolved.string();
}

// [ground.materials.NAME] scar: the soft-soil layer of a slip material, all four keys required
// (Lu et al. 2019 publish one set, the preset ramms_chant_sura_scar; no default fits every soil).
GroundMaterialSpec::Scar readScar(const Reader& r, const toml::table& t, const std::string& label) {
  r.checkKeys(t, sceneKeysOf("ground.materials.NAME.scar"), label + " scar");
  for (const std::string& key : sceneKeysOf("ground.materials.NAME.scar"))
    if (!t.get(key))
      r.fail(t, label + " scar needs density, fluid_drag, compaction_drag and modulus; '" + key +
                    "' is missing (or use the preset ramms_chant_sura_scar)");
  GroundMaterialSpec::Scar s;
  s.density = r.positive(*t.get("density"), "scar.density", " kg/m^3 (the soil's density)");
  s.fluidDrag = r.nonNegative(*t.get("fluid_drag"), "scar.fluid_drag", " (drag coefficient C_f)");
  s.compactionDrag =
      r.nonNegative(*t.get("compaction_drag"), "scar.compaction_drag", " (drag coefficient C_s)");
  s.modulus = r.positive(*t.get("modulus"), "scar.modulus", " MN/m^2 (deformation modulus M_e)");
  return s;
}

// [ground.materials.NAME]: the keys of its law only, each checked; a slip material needs all
// four of mu(s)'s coefficients (no published default fits every ground).
GroundMaterialSpec readGroundMaterial(const Reader& r, const toml::table& m,
                                      const std::string& name) {
  const std::string label = "[ground.materials." + name + "]";
  r.checkKeys(m, sceneKeysOf("ground.materials.NAME"), label);
  GroundMaterialSpec g;
  g.name = name;
  g.where = r.where(m);
  if (const auto* x = m.get("law")) {
    const std::string law = r.string(*x, "law");
    if (law == "slip")
      g.law = GroundLawKind::kSlip;
    else if (law != "stone")
      r.fail(*x,
             "'law' must be \"stone\" (STONE's bounce and rolling, the default) or \"slip\" "
             "(slippage-dependent friction, Leine et al. 2014), got \"" +
                 law + "\"");
  }
  const bool slip = g.law == GroundLawKind::kSlip;
  const std::vector<std::string> stoneKeys{"friction", "rolling_resistance",
                                           "tangential_restitution"},
      slipKeys{"mu_min", "mu_max", "kappa", "beta", "scar"};
  for (const std::string& key : slip ? stoneKeys : slipKeys)
    if (const auto* x = m.get(key))
      r.fail(*x, "'" + key + "' " +
                     (slip ? "is not used by law = \"slip\" (its friction is mu(s) from mu_min, "
                             "mu_max, kappa and beta)"
                           : "belongs to law = \"slip\"; give law = \"slip\" in " + label));
  if (const auto* x = m.get("restitution")) g.restitution = r.inRange(*x, "restitution", 0, 1);
  if (const auto* x = m.get("friction"))
    g.friction = r.nonNegative(*x, "friction", " (Coulomb coefficient)");
  if (const auto* x = m.get("rolling_resistance"))
    g.rollingResistance =
        r.nonNegative(*x, "rolling_resistance", " (tan of the rolling friction angle)");
  if (const auto* x = m.get("tangential_restitution"))
    g.tangentialRestitution = r.inRange(*x, "tangential_restitution", 0, 1);
  if (!slip) return g;
  for (const std::string key : {"mu_min", "mu_max", "kappa", "beta"})
    if (!m.get(key))
      r.fail(m, label + " has law = \"slip\" and needs mu_min, mu_max, kappa and beta; '" + key +
                    "' is missing (or use a preset: ramms_chant_sura, leine2014_demo)");
  g.muMin = r.nonNegative(*m.get("mu_min"), "mu_min", " (Coulomb coefficient)");
  g.muMax = r.nonNegative(*m.get("mu_max"), "mu_max", " (Coulomb coefficient)");
  if (*g.muMax < *g.muMin)
    r.fail(*m.get("mu_max"), "'mu_max' must be >= 'mu_min' (" + formatNumber(*g.muMin) +
                                 "): friction grows with slippage, got " + formatNumber(*g.muMax));
  g.kappa = r.nonNegative(*m.get("kappa"), "kappa", " 1/m (slippage hardening)");
  g.beta = r.nonNegative(*m.get("beta"), "beta", " 1/s (slippage softening)");
  if (const auto* x = m.get("scar")) g.scar = readScar(r, r.table(*x, "scar"), label);
  return g;
}

void readGround(const Reader& r, const toml::table& t, const fs::path& sceneFolder,
                SceneSpec& spec) {
  r.checkKeys(t, sceneKeysOf("ground"), "[ground]");
  if (const auto* n = t.get("edge")) {
    const std::string v = r.string(*n, "edge");
    if (v == "remove")
      spec.terrainEdge = TerrainEdge::kRemove;
    else if (v == "stop")
      spec.terrainEdge = TerrainEdge::kStop;
    else if (v == "wall")
      spec.terrainEdge = TerrainEdge::kWall;
    else
      r.fail(
          *n,
          "'edge' must be \"remove\" (the default without a plane), \"stop\" or \"wall\", got \"" +
              v + "\"");
  }
  if (const auto* n = t.get("plane")) spec.groundPlane = r.number(*n, "plane");
  if (const auto* n = t.get("heightfield")) {
    spec.terrainPath = existingFile(r, *n, "heightfield", sceneFolder, "terrain grid",
                                    " (a DEM GDAL reads, e.g. GeoTIFF or ESRI ASCII; relative "
                                    "paths resolve against the scene file's folder)");
  }
  if (const auto* n = t.get("offset")) {
    if (spec.terrainPath.empty())
      r.fail(*n, "'offset' moves the heightfield; give 'heightfield' too");
    spec.terrainShift = r.vec3(*n, "offset");
  }
  if (const auto* n = t.get("crs")) {
    if (spec.terrainPath.empty())
      r.fail(*n, "'crs' is the heightfield's coordinate reference system; give 'heightfield' too");
    spec.terrainCrs = r.string(*n, "crs");
    try {
      parseCrs(spec.terrainCrs);
    } catch (const std::invalid_argument& e) {
      r.fail(*n, std::string("'crs': ") + e.what());
    }
  }
  if (const auto* n = t.get("texture")) {
    if (spec.terrainPath.empty())
      r.fail(*n, "'texture' is draped on the heightfield; give 'heightfield' too");
    spec.terrainTexturePath =
        existingFile(r, *n, "texture", sceneFolder, "texture raster",
                     " (an RGB or grey raster GDAL reads, e.g. an orthophoto GeoTIFF; relative "
                     "paths resolve against the scene file's folder)");
  }
  if (const auto* n = t.get("materials")) {
    const toml::table& all = r.table(*n, "materials");
    for (auto&& [k, v] : all) {
      const std::string name(k.str());
      spec.groundMaterials.push_back(
          readGroundMaterial(r, r.table(v, "ground.materials." + name), name));
    }
  }
  // A material name must be a custom one or a preset.
  auto materialName = [&](const toml::node& n, const std::string& key) {
    const std::string name = r.string(n, key);
    std::vector<std::string> valid;
    for (const auto& g : spec.groundMaterials) valid.push_back(g.name);
    for (const auto& p : groundPresetNames()) valid.push_back(p);
    if (std::find(valid.begin(), valid.end(), name) != valid.end()) return name;
    std::string message = "unknown ground material '" + name + "'";
    if (auto guess = nearestName(name, valid))
      message += "; did you mean '" + *guess + "'?";
    else
      message += "; presets: " + joinNames(groundPresetNames()) + " (or define [ground.materials." +
                 name + "])";
    r.fail(n, message);
  };
  if (const auto* n = t.get("material")) spec.groundMaterial = materialName(*n, "material");
  if (const auto* n = t.get("classes")) {
    if (spec.terrainPath.empty())
      r.fail(*n, "'classes' is a raster on the heightfield's grid; give 'heightfield' too");
    if (spec.groundMaterial.empty())
      r.fail(*n, "give 'material' too: it applies where the class raster has no mapped class");
    spec.groundClassesPath = existingFile(r, *n, "classes", sceneFolder, "class raster");
    const toml::node* map = t.get("class_materials");
    if (map == nullptr) r.fail(*n, "give 'class_materials' too: a table class = \"material\"");
    const toml::table& m = r.table(*map, "class_materials");
    for (auto&& [k, v] : m) {
      int cls = -1;
      const std::string key(k.str());
      const auto res = std::from_chars(key.data(), key.data() + key.size(), cls);
      if (res.ec != std::errc() || res.ptr != key.data() + key.size() || cls < 0 || cls > 65535)
        r.fail(k.source(),
               "'class_materials' keys must be class numbers 0..65535, got '" + key + "'");
      spec.classMaterials.emplace_back(cls, materialName(v, "class_materials." + key));
    }
  } else if (const auto* n = t.get("class_materials")) {
    r.fail(*n, "'class_materials' needs 'classes' (the class raster)");
  }
  if (const auto* n = t.get("variability")) {
    const double v = r.number(*n, "variability");
    if (v < 0 || v >= 1)
      r.fail(*n,
             "'variability' must be >= 0 and < 1 (0.1: each coefficient within +-10 % per "
             "cell), got " +
                 formatNumber(v));
    if (v > 0 && spec.terrainPath.empty())
      r.fail(*n, "'variability' perturbs the ground per DEM cell; give 'heightfield' too");
    if (v > 0 && spec.groundMaterial.empty())
      r.fail(*n, "'variability' perturbs the ground material's coefficients; give 'material' too");
    spec.groundVariability = v;
  }
  if (const auto* n = t.get("variability_seed")) {
    if (!t.get("variability"))
      r.fail(*n, "'variability_seed' seeds 'variability'; give 'variability' too");
    spec.groundVariabilitySeed = static_cast<std::uint64_t>(
        r.integerInRange(*n, "variability_seed", 0, std::numeric_limits<std::int64_t>::max()));
  }
}

// --- [shapes.NAME] ------------------------------------------------------------------------

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

  if (const auto* n = t.get("scale")) {
    if (n->is_number()) {
      const double v = r.positive(*n, "scale", " (a factor on the mesh file's units)");
      s.scale = Vec3::Constant(v);
    } else if (n->is_array()) {
      s.scale = r.vec3(*n, "scale");
      for (int i = 0; i < 3; ++i) {
        // A zero factor flattens the mesh to no volume; negative ones would mirror it.
        if (!(s.scale[i] > 0))
          r.fail(*n, "'scale' factors must be > 0, got " + formatNumber(s.scale[i]));
      }
    } else {
      r.fail(*n,
             "'scale' must be a number or an array of 3 numbers [sx, sy, sz], got " + typeName(*n));
    }
  }
  readMass(r, t, label, s);
  if (const auto* n = t.get("up")) {
    const std::string up = r.string(*n, "up");
    if (up != "z" && up != "y")
      r.fail(*n,
             "'up' must be \"z\" (the default) or \"y\" (a y-up mesh, rotated so y becomes z), got "
             "\"" +
                 up + "\"");
    s.yUp = up == "y";
  }
  if (const auto* n = t.get("level"))
    s.level = static_cast<int>(r.integerInRange(*n, "level", kMinLevel, kMaxLevel));
  if (const auto* n = t.get("color")) s.color = r.color(*n, "color");
  if (const auto* n = t.get("smooth")) s.smoothDegrees = r.inRange(*n, "smooth", 0, 180);
  if (seeds == 0) return {s};
  std::vector<ShapeSpec> variants;
  for (std::int64_t k = 0; k < seeds; ++k) {
    ShapeSpec v = s;
    v.name = name + "#" + std::to_string(k);
    v.family = name;
    v.rock->seed = s.rock->seed + static_cast<std::uint64_t>(k);
    variants.push_back(std::move(v));
  }
  return variants;
}

void readShapes(const Reader& r, const toml::table& t, const fs::path& sceneFolder,
                SceneSpec& spec) {
  // Keep file order: shape indices pick default colours and must not depend on key sorting.
  std::vector<std::pair<const toml::key*, const toml::node*>> entries;
  for (auto&& [k, v] : t) entries.emplace_back(&k, &v);
  std::sort(entries.begin(), entries.end(), [](const auto& a, const auto& b) {
    return before(a.first->source(), b.first->source());
  });
  for (const auto& [k, v] : entries) {
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

// The names a scene's shapes go by in messages: each [shapes.NAME], a rock family once.
std::vector<std::string> shapeNames(const SceneSpec& spec) {
  std::vector<std::string> names;
  for (const auto& s : spec.shapes)
    if (s.family.empty())
      names.push_back(s.name);
    else if (names.empty() || names.back() != s.family)
      names.push_back(s.family);
  return names;
}

// The variants of rock family `name`, in seed order; empty when `name` is not a family.
std::vector<std::string> familyMembers(const SceneSpec& spec, const std::string& name) {
  std::vector<std::string> members;
  for (const auto& s : spec.shapes)
    if (s.family == name) members.push_back(s.name);
  return members;
}

bool isShapeName(const SceneSpec& spec, const std::string& name) {
  for (const auto& s : spec.shapes)
    if (s.name == name) return true;
  return false;
}

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

// Arrays of tables: `[[bodies]]`. A plain `[bodies]` table is the likely mistake.
const toml::array& arrayOfTables(const Reader& r, const toml::node& n, const std::string& name) {
  const toml::array* a = n.as_array();
  if (a == nullptr || !a->is_array_of_tables())
    r.fail(n, "'" + name + "' must be an array of tables (write each entry under [[" + name +
                  "]]), got " + typeName(n));
  return *a;
}

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

// --- [camera], [output] -------------------------------------------------------------------

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
  std::vector<std::pair<const toml::key*, const toml::node*>> entries;
  for (auto&& [k, v] : t) entries.emplace_back(&k, &v);
  std::sort(entries.begin(), entries.end(), [](const auto& a, const auto& b) {
    return before(a.first->source(), b.first->source());
  });
  for (const auto& [k, v] : entries) {
    const std::string name(k->str());
    const std::string label = "[cameras." + name + "]";
    if (name == "camera")
      r.fail(k->source(), "'camera' names the [camera] table; pick another name");
    spec.cameras.push_back(readCamera(r, r.table(*v, "cameras." + name), name, label, spec));
  }
}

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

// --- [ensemble] ---------------------------------------------------------------------------

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

}  // namespace

SceneSpec loadScene(const std::string& path) {
  SceneSpec spec;
  spec.path = path;
  spec.name = fs::path(path).stem().string();

  std::error_code ec;
  if (!fs::exists(path, ec)) throw InputError(path, "scene file not found");
  if (!fs::is_regular_file(path, ec)) throw InputError(path, "scene path is not a file");

  toml::table root;
  try {
    root = toml::parse_file(path);
  } catch (const toml::parse_error& e) {
    const auto& b = e.source().begin;
    throw InputError(sourceLocation(path, static_cast<int>(b.line), static_cast<int>(b.column)),
                     "TOML syntax error: " + std::string(e.description()));
  }

  const Reader r(path);
  r.checkKeys(root, sceneKeysOf(""), "the scene's top level");
  const fs::path sceneFolder = fs::path(path).parent_path();

  // Shapes before bodies and emitters (which name them); bodies and emitters before the camera
  // (whose `follow` is a body index).
  if (const auto* n = root.get("simulation")) readSimulation(r, r.table(*n, "simulation"), spec);
  if (const auto* n = root.get("contact")) readContact(r, r.table(*n, "contact"), spec.contact);
  if (const auto* n = root.get("ground")) readGround(r, r.table(*n, "ground"), sceneFolder, spec);
  if (const auto* n = root.get("light")) readLight(r, r.table(*n, "light"), spec);
  // A rock-fall scene (one with ground materials) rotates by the midpoint rule unless it says
  // otherwise: the paper's explicit Euler gains energy in free tumbling, and a rock's runout
  // depends on the spin it keeps in flight. Scenes without materials keep the paper's update.
  if (!spec.groundMaterial.empty() && root.at_path("simulation.rotation").node() == nullptr)
    spec.rotation = RotationUpdate::kMidpoint;
  if (const auto* n = root.get("shapes")) readShapes(r, r.table(*n, "shapes"), sceneFolder, spec);
  if (const auto* n = root.get("bodies")) readBodies(r, arrayOfTables(r, *n, "bodies"), spec);
  if (const auto* n = root.get("emitters")) readEmitters(r, arrayOfTables(r, *n, "emitters"), spec);
  if (const auto* n = root.get("camera"))
    spec.camera = readCamera(r, r.table(*n, "camera"), "camera", "[camera]", spec);
  if (const auto* n = root.get("cameras")) readCameras(r, r.table(*n, "cameras"), spec);
  if (const auto* n = root.get("output")) readOutput(r, r.table(*n, "output"), spec);
  if (const auto* n = root.get("ensemble"))
    readEnsemble(r, r.table(*n, "ensemble"), sceneFolder, spec);

  // Frame k is at k / fps for k = 0 .. floor(duration * fps): keep that count allocatable.
  if (spec.duration * spec.fps > kMaxSceneFrames) {
    const toml::node* n = root.at_path("simulation.duration").node();
    throw InputError(n != nullptr ? r.where(*n) : path,
                     "duration * fps = " + formatNumber(spec.duration * spec.fps) +
                         " frames; at most " + formatNumber(kMaxSceneFrames) + " are supported");
  }
  // Drawn frames: duration * fps / speed (slow motion makes more).
  if (spec.duration * spec.fps / spec.output.speed > kMaxSceneFrames) {
    const toml::node* n = root.at_path("output.speed").node();
    throw InputError(
        n != nullptr ? r.where(*n) : path,
        "duration * fps / speed = " + formatNumber(spec.duration * spec.fps / spec.output.speed) +
            " frames; at most " + formatNumber(kMaxSceneFrames) + " are supported");
  }
  return spec;
}

std::string frameSideProblem(const std::string& side, std::int64_t pixels) {
  if (pixels >= 1 && pixels <= kMaxImageSide) return "";
  return "the frame " + side + " must be 1.." + std::to_string(kMaxImageSide) + " pixels, got " +
         std::to_string(pixels);
}

void selectCamera(SceneSpec& spec, const std::string& name) {
  if (name == "camera") return;  // [camera], or the automatic camera without one
  std::string names = "camera";
  for (const CameraSpec& c : spec.cameras) {
    if (c.name == name) {
      spec.camera = c;
      return;
    }
    names += ", " + c.name;
  }
  throw InputError(spec.path, "no camera named '" + name + "'; the scene has: " + names);
}

}  // namespace vf

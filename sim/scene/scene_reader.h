// Private to sim/scene: what the scene loader's files share. loadScene (scene_loader.cpp) parses
// the TOML and hands each table to its reader, one file per group of tables
// (scene_read_ground.cpp, scene_read_shapes.cpp, scene_read_view.cpp, scene_read_ensemble.cpp).
// These files and scene_reader.cpp are the only ones in voxfall that include toml++; nothing
// outside sim/scene includes this header.
#pragma once

#include <toml++/toml.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "sim/core/error.h"
#include "sim/scene/scene.h"

namespace vf::scene_reading {

namespace fs = std::filesystem;

// The candidate a user most plausibly meant by `word`, or nothing when none is close.
std::optional<std::string> nearestName(std::string_view word,
                                       const std::vector<std::string>& candidates);
std::string joinNames(const std::vector<std::string>& names);
std::string formatNumber(double v);         // %.6g
std::string typeName(const toml::node& n);  // "table", "string", ... for messages
// Whether region `a` starts before `b` in the file.
bool before(const toml::source_region& a, const toml::source_region& b);

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

// The path in string `n` (key `key`), resolved against the scene's folder; it must name a file,
// else the error says "WHAT not found: 'PATH'" and then `hint`.
std::string existingFile(const Reader& r, const toml::node& n, const std::string& key,
                         const fs::path& sceneFolder, const std::string& what,
                         const std::string& hint = "");
// The entries of `t` in the order the file gives them (toml++ keeps keys sorted): whatever a
// table's entries number or colour by must not depend on key sorting.
std::vector<std::pair<const toml::key*, const toml::node*>> inFileOrder(const toml::table& t);
// Arrays of tables: `[[bodies]]`. A plain `[bodies]` table is the likely mistake.
const toml::array& arrayOfTables(const Reader& r, const toml::node& n, const std::string& name);
// The names a scene's shapes go by in messages: each [shapes.NAME], a rock family once.
std::vector<std::string> shapeNames(const SceneSpec& spec);
// The variants of rock family `name`, in seed order; empty when `name` is not a family.
std::vector<std::string> familyMembers(const SceneSpec& spec, const std::string& name);
bool isShapeName(const SceneSpec& spec, const std::string& name);

// The table readers, in the order loadScene calls them: shapes before bodies and emitters
// (which name them), bodies and emitters before cameras (whose `follow` is a body index).
void readSimulation(const Reader& r, const toml::table& t, SceneSpec& spec);
void readContact(const Reader& r, const toml::table& t, ContactMaterial& c);
void readGround(const Reader& r, const toml::table& t, const fs::path& sceneFolder,
                SceneSpec& spec);
void readForest(const Reader& r, const toml::table& t, const fs::path& sceneFolder,
                SceneSpec& spec);  // scene_read_forest.cpp
void readLight(const Reader& r, const toml::table& t, SceneSpec& spec);
void readShapes(const Reader& r, const toml::table& t, const fs::path& sceneFolder,
                SceneSpec& spec);
void readBodies(const Reader& r, const toml::array& bodies, SceneSpec& spec);
void readEmitters(const Reader& r, const toml::array& emitters, SceneSpec& spec);
CameraSpec readCamera(const Reader& r, const toml::table& t, const std::string& name,
                      const std::string& label, const SceneSpec& spec);
void readCameras(const Reader& r, const toml::table& t, SceneSpec& spec);
void readOutput(const Reader& r, const toml::table& t, SceneSpec& spec);
void readEnsemble(const Reader& r, const toml::table& t, const fs::path& sceneFolder,
                  SceneSpec& spec);
void readEvaluationLines(const Reader& r, const toml::array& lines, const fs::path& sceneFolder,
                         SceneSpec& spec);
void readBarriers(const Reader& r, const toml::array& barriers, const fs::path& sceneFolder,
                  SceneSpec& spec);

}  // namespace vf::scene_reading

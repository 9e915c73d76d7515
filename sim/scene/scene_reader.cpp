// The loader's shared helpers: name suggestions, the messages' wording, files and shape names.
#include "sim/scene/scene_reader.h"

#include <cstdio>
#include <limits>
#include <string>
#include <vector>

#include "sim/scene/scene_keys.h"

namespace vf::scene_reading {
namespace {

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

}  // namespace

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

// The path in string `n` (key `key`), resolved against the scene's folder; it must name a file,
// else the error says "WHAT not found: 'PATH'" and then `hint`.
std::string existingFile(const Reader& r, const toml::node& n, const std::string& key,
                         const fs::path& sceneFolder, const std::string& what,
                         const std::string& hint) {
  fs::path resolved(r.string(n, key));
  if (resolved.is_relative()) resolved = sceneFolder / resolved;
  resolved = resolved.lexically_normal();
  std::error_code ec;
  if (!fs::is_regular_file(resolved, ec))
    r.fail(n, what + " not found: '" + resolved.string() + "'" + hint);
  return resolved.string();
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

std::vector<std::pair<const toml::key*, const toml::node*>> inFileOrder(const toml::table& t) {
  std::vector<std::pair<const toml::key*, const toml::node*>> entries;
  for (auto&& [k, v] : t) entries.emplace_back(&k, &v);
  std::sort(entries.begin(), entries.end(), [](const auto& a, const auto& b) {
    return before(a.first->source(), b.first->source());
  });
  return entries;
}

// Arrays of tables: `[[bodies]]`. A plain `[bodies]` table is the likely mistake.
const toml::array& arrayOfTables(const Reader& r, const toml::node& n, const std::string& name) {
  const toml::array* a = n.as_array();
  if (a == nullptr || !a->is_array_of_tables())
    r.fail(n, "'" + name + "' must be an array of tables (write each entry under [[" + name +
                  "]]), got " + typeName(n));
  return *a;
}

}  // namespace vf::scene_reading

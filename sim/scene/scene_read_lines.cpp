// [[evaluation_lines]] and [[barriers]]: polylines on the terrain, where rock crossings are
// recorded and where nets stop rocks (docs/rockfall.md, "Evaluation lines", "Barriers").
// Points are checked here for form; whether they lie on the DEM, and a vector file's lines, are
// settled when the scene is built (scene_lines.cpp), where the DEM and its CRS are known.
#include "sim/scene/scene_keys.h"
#include "sim/scene/scene_reader.h"

namespace vf::scene_reading {
namespace {

// The polyline of table `t` (`name`, `points` or `file` and `layer`) of `[[table]]` entry `index`.
EvaluationLineSpec readPolyline(const Reader& r, const toml::table& t, const std::string& table,
                                std::size_t index, const fs::path& sceneFolder,
                                const SceneSpec& spec) {
  if (spec.terrainPath.empty())
    r.fail(t, "[[" + table +
                  "]] needs a terrain ([ground] heightfield): they are written in "
                  "the DEM's coordinates");
  EvaluationLineSpec line;
  line.where = r.where(t);
  line.name = (table == "barriers" ? "barrier " : "line ") + std::to_string(index);
  if (const auto* n = t.get("name")) line.name = r.string(*n, "name");
  const toml::node* points = t.get("points");
  const toml::node* file = t.get("file");
  if ((points == nullptr) == (file == nullptr))
    r.fail(t, "[[" + table + "]] '" + line.name +
                  "' needs exactly one of 'points' ([[x, y], ...] in the DEM's coordinates) or "
                  "'file' (a vector file of lines)");
  if (const auto* n = t.get("layer")) {
    if (file == nullptr) r.fail(*n, "'layer' needs 'file'");
    line.layer = r.string(*n, "layer");
  }
  if (file != nullptr) {
    line.file = existingFile(r, *file, "file", sceneFolder, "vector file");
    return line;
  }
  const toml::array* a = points->as_array();
  if (a == nullptr || a->size() < 2)
    r.fail(*points,
           "'points' must be an array of at least 2 [x, y] points (the DEM's "
           "coordinates, m), got " +
               (a == nullptr ? typeName(*points) : "an array of " + std::to_string(a->size())));
  for (std::size_t k = 0; k < a->size(); ++k) {
    const auto v = r.numbers(*a->get(k), "points[" + std::to_string(k) + "]", 2,
                             "an array of 2 numbers [x, y]");
    line.points.push_back({v[0], v[1]});
    line.pointWhere.push_back(r.where(*a->get(k)));
  }
  return line;
}

}  // namespace

void readEvaluationLines(const Reader& r, const toml::array& lines, const fs::path& sceneFolder,
                         SceneSpec& spec) {
  for (std::size_t l = 0; l < lines.size(); ++l) {
    const toml::table& t = r.table(*lines.get(l), "evaluation_lines[" + std::to_string(l) + "]");
    r.checkKeys(t, sceneKeysOf("evaluation_lines"), "[[evaluation_lines]]");
    spec.evaluationLines.push_back(readPolyline(r, t, "evaluation_lines", l, sceneFolder, spec));
  }
}

namespace {

// `KEY_field`: the attribute of a barrier file's features that gives KEY per feature, in place
// of the table's KEY (one or the other); "" when not given.
std::string readField(const Reader& r, const toml::table& t, const std::string& key,
                      const EvaluationLineSpec& line) {
  const std::string name = key + "_field";
  const toml::node* n = t.get(name);
  if (n == nullptr) return "";
  if (line.file.empty()) r.fail(*n, "'" + name + "' needs 'file' (a vector file of lines)");
  if (const toml::node* value = t.get(key))
    r.fail(*value, "give either '" + key + "' or '" + name + "', not both");
  return r.string(*n, name);
}

}  // namespace

void readBarriers(const Reader& r, const toml::array& barriers, const fs::path& sceneFolder,
                  SceneSpec& spec) {
  for (std::size_t l = 0; l < barriers.size(); ++l) {
    const toml::table& t = r.table(*barriers.get(l), "barriers[" + std::to_string(l) + "]");
    r.checkKeys(t, sceneKeysOf("barriers"), "[[barriers]]");
    BarrierSpec b;
    b.line = readPolyline(r, t, "barriers", l, sceneFolder, spec);
    b.heightField = readField(r, t, "height", b.line);
    b.capacityField = readField(r, t, "capacity", b.line);
    if (b.heightField.empty())
      b.height = r.positive(r.require(t, "height", "[[barriers]]"), "height", " m");
    if (b.capacityField.empty())
      b.capacity = r.nonNegative(r.require(t, "capacity", "[[barriers]]"), "capacity", " kJ");
    if (const auto* n = t.get("thickness")) b.thickness = r.positive(*n, "thickness", " m");
    spec.barriers.push_back(std::move(b));
  }
}

}  // namespace vf::scene_reading

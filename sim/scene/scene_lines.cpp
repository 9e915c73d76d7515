// The scene's evaluation lines on its terrain: from the DEM file's coordinates, in which a user
// writes them (or a vector file holds them, read into the DEM's CRS), to world coordinates,
// each vertex checked to lie on the DEM.
#include <cmath>
#include <cstdio>
#include <optional>

#include "sim/core/error.h"
#include "sim/scene/scene.h"
#include "sim/shape/vector_import.h"

namespace vf {
namespace {

// The polylines of one [[evaluation_lines]] table, DEM file coordinates, each with its name and
// where each vertex came from (for errors).
struct SourceLine {
  std::string name;
  std::vector<Point2> points;
  std::vector<std::string> pointWhere;
  std::optional<VectorFeature> feature;  // the file's feature it came from; none for `points`
};

std::vector<SourceLine> sourceLines(const EvaluationLineSpec& s, const Heightfield& dem,
                                    const std::string& what) {
  if (s.file.empty()) return {SourceLine{s.name, s.points, s.pointWhere, std::nullopt}};
  std::vector<SourceLine> out;
  const std::vector<VectorFeature> features = readVectorFile(s.file, dem.crsWkt, s.layer);
  for (const VectorFeature& f : features) {
    const std::string where = s.file + ": feature " + std::to_string(f.id);
    if (f.kind != VectorFeature::Kind::kLine)
      throw InputError(where, std::string("is a ") +
                                  (f.kind == VectorFeature::Kind::kPoint ? "point" : "polygon") +
                                  "; " + what + "s must be lines (LineString)");
    SourceLine line;
    line.name = features.size() == 1 ? s.name : s.name + "#" + std::to_string(f.id);
    line.points = f.rings.at(0);
    line.pointWhere.assign(line.points.size(), where);
    line.feature = f;
    if (line.points.size() < 2) throw InputError(where, "a line needs at least 2 vertices");
    out.push_back(std::move(line));
  }
  if (out.empty()) throw InputError(s.file, "holds no line for the " + what);
  return out;
}

// The polylines of one table in world coordinates, each vertex checked to lie on the DEM.
std::vector<SourceLine> worldLines(const EvaluationLineSpec& s, const Heightfield& dem,
                                   const std::string& what, const std::string& terrainPath) {
  std::vector<SourceLine> out = sourceLines(s, dem, what);
  for (SourceLine& line : out)
    for (std::size_t k = 0; k < line.points.size(); ++k) {
      Point2& p = line.points[k];
      const double x = p[0] + dem.shift.x(), y = p[1] + dem.shift.y();
      if (std::isnan(dem.heightAt(x, y))) {
        const double fx = dem.x0 - dem.shift.x(), fy = dem.y0 - dem.shift.y();
        char text[400];
        std::snprintf(text, sizeof text,
                      "point %zu (%.3f, %.3f) lies outside the DEM or over NODATA (the grid "
                      "covers x %.3f .. %.3f, y %.3f .. %.3f in the DEM's coordinates, before "
                      "[ground] offset)",
                      k, p[0], p[1], fx, fx + (dem.nx - 1) * dem.cell, fy,
                      fy + (dem.ny - 1) * dem.cell);
        throw InputError(line.pointWhere[k],
                         what + " '" + line.name + "' " + text + ": '" + terrainPath + "'");
      }
      p = {x, y};
    }
  return out;
}

// A barrier's height or capacity: the table's `value`, or the line's feature's `field`, which
// must be set and at least `min` (and above it when `strict`).
double barrierValue(const SourceLine& line, const BarrierSpec& s, double value,
                    const std::string& field, const char* what, double min, bool strict) {
  if (field.empty()) return value;
  const std::string where = s.line.file + ": feature " + std::to_string(line.feature->id);
  const std::optional<double> v = line.feature->number(field);
  if (!v)
    throw InputError(where, "barrier '" + line.name + "' has no number in field '" + field +
                                "' (its " + what + ")");
  if (!std::isfinite(*v) || (strict ? *v <= min : *v < min)) {
    char text[200];
    std::snprintf(text, sizeof text, "'%s' (its %s) must be %s %g, got %g", field.c_str(), what,
                  strict ? ">" : ">=", min, *v);
    throw InputError(where, "barrier '" + line.name + "': " + text);
  }
  return *v;
}

}  // namespace

std::vector<EvaluationLine> sceneEvaluationLines(const SceneSpec& spec, const Heightfield& dem) {
  std::vector<EvaluationLine> out;
  for (const EvaluationLineSpec& s : spec.evaluationLines)
    for (SourceLine& l : worldLines(s, dem, "evaluation line", spec.terrainPath))
      out.push_back(EvaluationLine{l.name, l.points});
  return out;
}

std::vector<Barrier> sceneBarriers(const SceneSpec& spec, const Heightfield& dem) {
  std::vector<Barrier> out;
  for (const BarrierSpec& s : spec.barriers) {
    for (SourceLine& l : worldLines(s.line, dem, "barrier", spec.terrainPath)) {
      const double height = barrierValue(l, s, s.height, s.heightField, "height, m", 0, true);
      const double capacity =
          barrierValue(l, s, s.capacity, s.capacityField, "capacity, kJ", 0, false);
      out.push_back(Barrier{l.name, l.points, height, capacity * 1000, s.thickness});
    }
  }
  return out;
}

std::shared_ptr<const BarrierMonitor> attachBarriers(
    World& world, const std::vector<Barrier>& barriers,
    const std::vector<std::vector<BarrierPiece>>& pieces) {
  if (barriers.empty()) return nullptr;
  auto monitor = std::make_shared<BarrierMonitor>(BarrierMonitor::build(world, barriers, pieces));
  monitor->observe(world);  // the motion before the first step
  world.addStepListener([monitor](World& w) { monitor->observe(w); });
  return monitor;
}

}  // namespace vf

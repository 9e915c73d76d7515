// Release sources placed on the DEM and drawn from (see release_sources.h).
#include "sim/ensemble/release_sources.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "sim/core/error.h"
#include "sim/core/prng.h"
#include "sim/shape/heightfield.h"
#include "sim/shape/vector_import.h"

namespace vf {
namespace {

// Area points are drawn by rejection from the area's bounding box; an area whose box is mostly
// outside it (or over NODATA) could take long, so give up with a message.
constexpr int kMaxReleaseTries = 100000;

// Even-odd rule over every ring (crossings of a ray towards +x): holes are outside.
bool insideRings(const std::vector<std::vector<Point2>>& rings, double x, double y) {
  bool inside = false;
  for (const auto& poly : rings)
    for (std::size_t i = 0, j = poly.size() - 1; i < poly.size(); j = i++) {
      const Point2& a = poly[i];
      const Point2& b = poly[j];
      if ((a[1] > y) != (b[1] > y) && x < (b[0] - a[0]) * (y - a[1]) / (b[1] - a[1]) + a[0])
        inside = !inside;
    }
  return inside;
}

double ringArea(const std::vector<Point2>& ring) {
  double twice = 0;  // shoelace
  for (std::size_t i = 0; i < ring.size(); ++i) {
    const Point2& p = ring[i];
    const Point2& q = ring[(i + 1) % ring.size()];
    twice += p[0] * q[1] - q[0] * p[1];
  }
  return 0.5 * std::abs(twice);
}

double lineLength(const std::vector<Point2>& line) {
  double total = 0;
  for (std::size_t i = 1; i < line.size(); ++i)
    total += std::hypot(line[i][0] - line[i - 1][0], line[i][1] - line[i - 1][1]);
  return total;
}

// The index of the entry of cumulative weights `c` that u in [0, 1) falls in.
std::size_t pick(const std::vector<double>& c, double u) {
  const double target = u * c.back();
  for (std::size_t k = 0; k < c.size(); ++k)
    if (target < c[k]) return k;
  return c.size() - 1;
}

std::string formatPoint(double x, double y) {
  char buf[96];
  std::snprintf(buf, sizeof buf, "(%.3f, %.3f)", x, y);
  return buf;
}

// `p` (DEM coordinates) in world coordinates, or an InputError at `where` when it lies off the
// DEM's data.
Point2 placed(const Heightfield& dem, const std::string& demPath, const Point2& p,
              const std::string& where, const std::string& what) {
  const Point2 w{p[0] + dem.shift.x(), p[1] + dem.shift.y()};
  if (!std::isnan(dem.heightAt(w[0], w[1]))) return w;
  const double x0 = dem.x0 - dem.shift.x(), y0 = dem.y0 - dem.shift.y();
  char range[160];
  std::snprintf(range, sizeof range, "x %.3f .. %.3f, y %.3f .. %.3f", x0,
                x0 + (dem.nx - 1) * dem.cell, y0, y0 + (dem.ny - 1) * dem.cell);
  throw InputError(where, what + " " + formatPoint(p[0], p[1]) + " lies outside the DEM '" +
                              demPath + "' or over NODATA (the grid covers " + range +
                              " in the DEM's coordinates)");
}

}  // namespace

ReleaseSources::ReleaseSources(const std::vector<ReleaseSpec>& specs,
                               std::shared_ptr<const Heightfield> dem, const std::string& demPath)
    : dem_(std::move(dem)) {
  double total = 0;
  for (const ReleaseSpec& s : specs) {
    Source source;
    switch (s.kind) {
      case ReleaseKind::kArea:
      case ReleaseKind::kLine:
      case ReleaseKind::kPoints:
        source.parts.push_back(inlinePart(s, demPath));
        break;
      case ReleaseKind::kCells:
        source.parts.push_back(cellsPart(s));
        break;
      case ReleaseKind::kFile:
        addFileParts(s, demPath, source);
        break;
    }
    if (source.partWeights.empty()) source.partWeights.push_back(1);
    total += s.weight;
    sourceWeights_.push_back(total);
    sources_.push_back(std::move(source));
  }
}

ReleaseSources::Part ReleaseSources::inlinePart(const ReleaseSpec& s,
                                                const std::string& demPath) const {
  Part p;
  p.form = s.kind == ReleaseKind::kArea   ? Form::kArea
           : s.kind == ReleaseKind::kLine ? Form::kLine
                                          : Form::kPoint;
  p.key = s.key;
  p.rings.emplace_back();
  for (std::size_t i = 0; i < s.points.size(); ++i)
    p.rings[0].push_back(placed(*dem_, demPath, s.points[i], s.pointWhere[i],
                                "'" + s.key + "[" + std::to_string(i) + "]'"));
  return p;
}

ReleaseSources::Part ReleaseSources::cellsPart(const ReleaseSpec& s) const {
  const Heightfield& dem = *dem_;
  const Heightfield cells = loadDem(s.path);
  // The source raster lies on the DEM's file grid: compare before the scene's offset.
  const double x0 = dem.x0 - dem.shift.x(), y0 = dem.y0 - dem.shift.y();
  if (cells.nx != dem.nx || cells.ny != dem.ny || std::abs(cells.x0 - x0) > 1e-6 * dem.cell ||
      std::abs(cells.y0 - y0) > 1e-6 * dem.cell ||
      std::abs(cells.cell - dem.cell) > 1e-9 * dem.cell)
    throw InputError(s.where, "'" + s.key + "' raster must lie on the DEM's grid (" +
                                  std::to_string(dem.nx) + " x " + std::to_string(dem.ny) +
                                  " samples, same origin and cell size), got " +
                                  std::to_string(cells.nx) + " x " + std::to_string(cells.ny));
  Part p;
  p.form = Form::kCell;
  p.key = s.key;
  for (std::size_t k = 0; k < cells.z.size(); ++k)
    if (!std::isnan(cells.z[k]) && cells.z[k] != 0 && !std::isnan(dem.z[k]))
      p.cells.push_back(static_cast<std::int32_t>(k));
  if (p.cells.empty())
    throw InputError(s.where,
                     "'" + s.key + "' raster has no source cell (a non-zero value over DEM data)");
  return p;
}

// Each feature of the file is a part, weighted by its `weight_field` or by its size.
void ReleaseSources::addFileParts(const ReleaseSpec& s, const std::string& demPath,
                                  Source& source) const {
  const auto features = readVectorFile(s.path, dem_->crsWkt, s.layer);
  double total = 0;
  for (const VectorFeature& f : features) {
    Part p;
    p.form = f.kind == VectorFeature::Kind::kPolygon ? Form::kArea
             : f.kind == VectorFeature::Kind::kLine  ? Form::kLine
                                                     : Form::kPoint;
    p.key = s.key + " feature " + std::to_string(f.id);
    if (!source.parts.empty() && p.form != source.parts.front().form && s.weightField.empty())
      throw InputError(s.path,
                       "the file mixes points, lines and areas; give 'weight_field' (a "
                       "numeric attribute) to say how often each feature releases");
    for (const auto& ring : f.rings) {
      p.rings.emplace_back();
      for (const Point2& v : ring)
        p.rings.back().push_back(placed(*dem_, demPath, v, s.path, p.key + " vertex"));
    }
    double w = p.form == Form::kArea   ? ringArea(p.rings[0]) - holesArea(p)
               : p.form == Form::kLine ? lineLength(p.rings[0])
                                       : 1.0;
    if (!s.weightField.empty()) {
      const auto given = f.number(s.weightField);
      if (!given)
        throw InputError(s.path, p.key + " has no numeric '" + s.weightField + "' attribute");
      w = *given;
    }
    if (!(w > 0) || !std::isfinite(w))
      throw InputError(s.path, p.key + " has weight " + std::to_string(w) +
                                   (s.weightField.empty() ? " (its size)" : "") +
                                   "; every feature needs a weight > 0");
    total += w;
    source.partWeights.push_back(total);
    source.parts.push_back(std::move(p));
  }
}

double ReleaseSources::holesArea(const Part& p) {
  double holes = 0;
  for (std::size_t k = 1; k < p.rings.size(); ++k) holes += ringArea(p.rings[k]);
  return holes;
}

Point2 ReleaseSources::draw(std::uint64_t seed, int* source) const {
  Prng rng(seed);
  const std::size_t k = sources_.size() > 1 ? pick(sourceWeights_, rng.uniform()) : 0;
  if (source) *source = static_cast<int>(k);
  const Source& s = sources_[k];
  const Part& p =
      s.parts.size() > 1 ? s.parts[pick(s.partWeights, rng.uniform())] : s.parts.front();
  return drawInPart(p, rng);
}

Point2 ReleaseSources::drawInPart(const Part& p, Prng& rng) const {
  const Heightfield& dem = *dem_;
  static const std::vector<Point2> kNoRing;  // a cells part has none
  const std::vector<Point2>& ring = p.rings.empty() ? kNoRing : p.rings[0];
  switch (p.form) {
    case Form::kPoint: {
      const std::size_t n = ring.size();
      return ring[std::min(n - 1, static_cast<std::size_t>(rng.uniform() * n))];
    }
    case Form::kLine: {
      double along = rng.uniform() * lineLength(ring);
      for (std::size_t i = 1; i < ring.size(); ++i) {
        const Point2& a = ring[i - 1];
        const Point2& b = ring[i];
        const double len = std::hypot(b[0] - a[0], b[1] - a[1]);
        if (along <= len || i + 1 == ring.size()) {
          const double f = len > 0 ? std::min(1.0, along / len) : 0.0;
          return {a[0] + f * (b[0] - a[0]), a[1] + f * (b[1] - a[1])};
        }
        along -= len;
      }
      return ring.back();
    }
    case Form::kArea: {
      double x0 = INFINITY, x1 = -INFINITY, y0 = INFINITY, y1 = -INFINITY;
      for (const Point2& v : ring) {
        x0 = std::min(x0, v[0]), x1 = std::max(x1, v[0]);
        y0 = std::min(y0, v[1]), y1 = std::max(y1, v[1]);
      }
      for (int k = 0; k < kMaxReleaseTries; ++k) {
        const double x = rng.uniform(x0, x1), y = rng.uniform(y0, y1);
        if (insideRings(p.rings, x, y) && !std::isnan(dem.heightAt(x, y))) return {x, y};
      }
      throw InputError(p.key, "no point with DEM data found inside '" + p.key + "' in " +
                                  std::to_string(kMaxReleaseTries) + " tries");
    }
    case Form::kCell: {
      const std::size_t n = p.cells.size();
      const std::int32_t c = p.cells[std::min(n - 1, static_cast<std::size_t>(rng.uniform() * n))];
      const double u = rng.uniform(-0.5, 0.5), v = rng.uniform(-0.5, 0.5);
      return {dem.x0 + (c % dem.nx + u) * dem.cell, dem.y0 + (c / dem.nx + v) * dem.cell};
    }
  }
  return ring.front();
}

std::vector<std::vector<Point2>> ReleaseSources::outlines() const {
  const Heightfield& dem = *dem_;
  std::vector<std::vector<Point2>> out;
  const double h = 0.5 * dem.cell;
  for (const Source& s : sources_)
    for (const Part& p : s.parts) {
      // Maps close an outline of three or more points: points and lines go out in pieces.
      if (p.form == Form::kPoint) {
        for (const Point2& v : p.rings[0]) out.push_back({v});
        continue;
      }
      if (p.form == Form::kLine) {
        for (std::size_t i = 1; i < p.rings[0].size(); ++i)
          out.push_back({p.rings[0][i - 1], p.rings[0][i]});
        continue;
      }
      for (const auto& ring : p.rings) out.push_back(ring);
      for (std::int32_t c : p.cells) {
        const double x = dem.x0 + (c % dem.nx) * dem.cell, y = dem.y0 + (c / dem.nx) * dem.cell;
        out.push_back({{x - h, y - h}, {x + h, y - h}, {x + h, y + h}, {x - h, y + h}});
      }
    }
  return out;
}

}  // namespace vf

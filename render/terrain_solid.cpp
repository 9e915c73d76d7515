#include "render/terrain_solid.h"

#include <algorithm>
#include <cstdint>

namespace vf {
namespace {

// Appends the quad from top edge p -> q down to `base`, wound to face `outward`.
void addWall(TriMesh& m, Vec3 p, Vec3 q, double base, const Vec3& outward) {
  if (p.z() <= base && q.z() <= base) return;  // no height: nothing to see or to cast
  Vec3 pb(p.x(), p.y(), base), qb(q.x(), q.y(), base);
  // The quad (pb, qb, q, p) faces along (qb - pb) x up; swap the ends to face the other way.
  if ((qb - pb).cross(Vec3::UnitZ()).dot(outward) < 0) {
    std::swap(p, q);
    std::swap(pb, qb);
  }
  const auto first = static_cast<std::uint32_t>(m.vertices.size());
  m.vertices.insert(m.vertices.end(), {pb, qb, q, p});
  // An end at the base makes one of the two triangles a line: left out.
  if (q.z() > base) m.triangles.push_back({first, first + 1, first + 2});
  if (p.z() > base) m.triangles.push_back({first, first + 2, first + 3});
}

}  // namespace

double terrainBase(const Heightfield& h, std::optional<double> floor) {
  if (floor && *floor <= h.zMin) return *floor;
  return h.zMin - std::max(h.cell, 0.05 * (h.zMax - h.zMin));
}

TriMesh terrainSides(const Heightfield& h, double base, bool closeBase) {
  TriMesh m;
  auto sample = [&](int i, int j) {
    return Vec3(h.x0 + i * h.cell, h.y0 + j * h.cell, h.at(i, j));
  };
  for (int j = 0; j + 1 < h.ny; ++j) {
    for (int i = 0; i + 1 < h.nx; ++i) {
      if (!h.hasCell(i, j)) continue;
      // hasCell is false outside the grid, so the border needs no case of its own.
      if (!h.hasCell(i, j - 1)) addWall(m, sample(i, j), sample(i + 1, j), base, -Vec3::UnitY());
      if (!h.hasCell(i, j + 1))
        addWall(m, sample(i, j + 1), sample(i + 1, j + 1), base, Vec3::UnitY());
      if (!h.hasCell(i - 1, j)) addWall(m, sample(i, j), sample(i, j + 1), base, -Vec3::UnitX());
      if (!h.hasCell(i + 1, j))
        addWall(m, sample(i + 1, j), sample(i + 1, j + 1), base, Vec3::UnitX());
    }
  }
  // The base: one quad per run of cells with data along each row, facing down.
  for (int j = 0; closeBase && j + 1 < h.ny; ++j) {
    for (int i = 0; i + 1 < h.nx;) {
      if (!h.hasCell(i, j)) {
        ++i;
        continue;
      }
      int end = i;
      while (end + 1 < h.nx && h.hasCell(end, j)) ++end;  // cells i .. end - 1
      const double xa = h.x0 + i * h.cell, xb = h.x0 + end * h.cell;
      const double ya = h.y0 + j * h.cell, yb = h.y0 + (j + 1) * h.cell;
      const auto first = static_cast<std::uint32_t>(m.vertices.size());
      m.vertices.insert(m.vertices.end(), {Vec3(xa, ya, base), Vec3(xa, yb, base),
                                           Vec3(xb, yb, base), Vec3(xb, ya, base)});
      // Counter-clockwise seen from below: normal -z.
      m.triangles.push_back({first, first + 1, first + 2});
      m.triangles.push_back({first, first + 2, first + 3});
      i = end;
    }
  }
  return m;
}

}  // namespace vf

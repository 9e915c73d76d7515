#include "sim/shape/heightfield.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "sim/geometry/mesh_bvh.h"

namespace vf {

namespace {

// The upward unit normal of a counter-clockwise (seen from above) triangle: normalAt's and
// minNormalZNear's one expression.
Vec3 unitNormal(const Vec3 t[3]) { return (t[1] - t[0]).cross(t[2] - t[0]).normalized(); }

}  // namespace

Vec3 Heightfield::normalAt(double x, double y) const {
  const double gx = (x - x0) / cell, gy = (y - y0) / cell;
  const int i = cellIndex(gx, nx - 2), j = cellIndex(gy, ny - 2);
  if (!hasCell(i, j)) return Vec3::UnitZ();
  Vec3 tri[2][3];
  cellTriangles(i, j, tri);
  return unitNormal((gx - i) >= (gy - j) ? tri[0] : tri[1]);
}

double Heightfield::minNormalZNear(double x, double y, double r) const {
  int i0, i1, j0, j1;
  cellRange(x, y, r, i0, i1, j0, j1);
  double least = 1;
  Vec3 tri[2][3];
  for (int j = j0; j <= j1; ++j)
    for (int i = i0; i <= i1; ++i) {
      if (!hasCell(i, j)) continue;
      cellTriangles(i, j, tri);
      least = std::min({least, unitNormal(tri[0]).z(), unitNormal(tri[1]).z()});
    }
  return least;
}

bool Heightfield::sphereAbove(const Vec3& c, double r) const {
  const double xEnd = x0 + (nx - 1) * cell, yEnd = y0 + (ny - 1) * cell;
  if (!(c.x() - r > x0 && c.y() - r > y0 && c.x() + r < xEnd && c.y() + r < yEnd)) return false;
  const double reach = r * (1 + 1e-9) + 1e-9, reach2 = reach * reach;
  // The plane of the triangle under the centre (heightAt's): the centre must lie above it,
  // farther than r (fartherAbove).
  const double gx = (c.x() - x0) / cell, gy = (c.y() - y0) / cell;
  const int ic = cellIndex(gx, nx - 2), jc = cellIndex(gy, ny - 2);
  if (!hasCell(ic, jc)) return false;
  const double u = gx - ic, v = gy - jc;
  const double z00 = at(ic, jc), z10 = at(ic + 1, jc), z01 = at(ic, jc + 1),
               z11 = at(ic + 1, jc + 1);
  const double a = u >= v ? z10 - z00 : z11 - z01, b = u >= v ? z11 - z10 : z01 - z00;
  const double d = c.z() - (z00 + u * a + v * b);
  if (!fartherAbove(d, a, b, reach2)) return false;
  // Then every triangle under the square out of reach.
  int i0, i1, j0, j1;
  cellRange(c.x(), c.y(), r, i0, i1, j0, j1);
  Vec3 tri[2][3];
  TriangleFeature feature;
  for (int j = j0; j <= j1; ++j)
    for (int i = i0; i <= i1; ++i) {
      if (!hasCell(i, j)) return false;
      cellTriangles(i, j, tri);
      for (const auto& t : tri) {
        const Vec3 normal = (t[1] - t[0]).cross(t[2] - t[0]);  // a triangle lies in its plane
        const double s = normal.dot(c - t[0]);
        if (s * s > reach2 * normal.squaredNorm()) continue;
        if ((c - closestPointOnTriangle(c, t[0], t[1], t[2], feature)).squaredNorm() <= reach2)
          return false;
      }
    }
  return true;
}

double Heightfield::maxHeightNear(double x, double y, double r) const {
  int i0, i1, j0, j1;
  cellRange(x, y, r, i0, i1, j0, j1);
  double top = -INFINITY;
  for (int j = j0; j <= j1 + 1 && j < ny; ++j)  // a cell's samples run to i + 1, j + 1
    for (int i = i0; i <= i1 + 1 && i < nx; ++i)
      if (!std::isnan(at(i, j))) top = std::max(top, at(i, j));
  return top;
}

double Heightfield::surfaceUnder(const std::vector<Vec3>& pts, double bottom) const {
  double gap = INFINITY;
  for (const Vec3& p : pts) {
    const double h = heightAt(p.x(), p.y());
    if (!std::isnan(h)) gap = std::min(gap, p.z() - h);
  }
  return std::isfinite(gap) ? bottom - gap : -INFINITY;
}

void Heightfield::cellTriangles(int i, int j, Vec3 tri[2][3]) const {
  const Vec3 p00(x0 + i * cell, y0 + j * cell, at(i, j));
  const Vec3 p10(x0 + (i + 1) * cell, y0 + j * cell, at(i + 1, j));
  const Vec3 p01(x0 + i * cell, y0 + (j + 1) * cell, at(i, j + 1));
  const Vec3 p11(x0 + (i + 1) * cell, y0 + (j + 1) * cell, at(i + 1, j + 1));
  tri[0][0] = p00, tri[0][1] = p10, tri[0][2] = p11;
  tri[1][0] = p00, tri[1][1] = p11, tri[1][2] = p01;
}

TriMesh Heightfield::toMesh() const {
  TriMesh m;
  m.vertices.reserve(z.size());
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i)
      m.vertices.push_back(Vec3(x0 + i * cell, y0 + j * cell, std::isnan(at(i, j)) ? 0 : at(i, j)));
  auto id = [&](int i, int j) { return static_cast<std::uint32_t>(j * nx + i); };
  for (int j = 0; j + 1 < ny; ++j)
    for (int i = 0; i + 1 < nx; ++i)
      if (hasCell(i, j)) {
        m.triangles.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
        m.triangles.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
      }
  return m;
}

void shiftHeightfield(Heightfield& h, const Vec3& shift) {
  h.x0 += shift.x();
  h.y0 += shift.y();
  for (double& v : h.z) v += shift.z();  // NaN stays NaN
  h.zMin += shift.z();
  h.zMax += shift.z();
  h.shift += shift;
}

}  // namespace vf

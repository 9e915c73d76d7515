#include "sim/shape/heightfield.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace vf {

bool Heightfield::hasCell(int i, int j) const {
  return i >= 0 && j >= 0 && i + 1 < nx && j + 1 < ny && !std::isnan(at(i, j)) &&
         !std::isnan(at(i + 1, j)) && !std::isnan(at(i, j + 1)) && !std::isnan(at(i + 1, j + 1));
}

double Heightfield::heightAt(double x, double y) const {
  const double gx = (x - x0) / cell, gy = (y - y0) / cell;
  const double fi = std::floor(gx), fj = std::floor(gy);
  // The far edge of the grid belongs to the last cell.
  const int i = static_cast<int>(std::min(fi, static_cast<double>(nx - 2)));
  const int j = static_cast<int>(std::min(fj, static_cast<double>(ny - 2)));
  if (!(gx >= 0 && gy >= 0 && gx <= nx - 1 && gy <= ny - 1) || !hasCell(i, j))
    return std::numeric_limits<double>::quiet_NaN();
  const double u = gx - i, v = gy - j;
  const double z00 = at(i, j), z10 = at(i + 1, j), z01 = at(i, j + 1), z11 = at(i + 1, j + 1);
  if (u >= v) return z00 + u * (z10 - z00) + v * (z11 - z10);  // triangle (p00, p10, p11)
  return z00 + v * (z01 - z00) + u * (z11 - z01);              // triangle (p00, p11, p01)
}

Vec3 Heightfield::normalAt(double x, double y) const {
  const double gx = (x - x0) / cell, gy = (y - y0) / cell;
  const int i = static_cast<int>(std::clamp(std::floor(gx), 0.0, static_cast<double>(nx - 2)));
  const int j = static_cast<int>(std::clamp(std::floor(gy), 0.0, static_cast<double>(ny - 2)));
  if (!hasCell(i, j)) return Vec3::UnitZ();
  Vec3 tri[2][3];
  cellTriangles(i, j, tri);
  const Vec3* t = (gx - i) >= (gy - j) ? tri[0] : tri[1];
  return (t[1] - t[0]).cross(t[2] - t[0]).normalized();
}

void Heightfield::cellRange(double x, double y, double r, int& i0, int& i1, int& j0,
                            int& j1) const {
  auto lo = [&](double v, int n) {
    return static_cast<int>(std::clamp(std::floor(v / cell), 0.0, static_cast<double>(n - 2)));
  };
  const double gx0 = x - r - x0, gx1 = x + r - x0, gy0 = y - r - y0, gy1 = y + r - y0;
  const double wx = (nx - 1) * cell, wy = (ny - 1) * cell;
  if (gx1 < 0 || gy1 < 0 || gx0 > wx || gy0 > wy) {
    i0 = j0 = 0;
    i1 = j1 = -1;
    return;
  }
  i0 = lo(gx0, nx);
  i1 = lo(gx1, nx);
  j0 = lo(gy0, ny);
  j1 = lo(gy1, ny);
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

double Heightfield::surfaceBoundNear(double x, double y, double r) const {
  int i0, i1, j0, j1;
  cellRange(x, y, r, i0, i1, j0, j1);
  double top = -INFINITY;
  // The square in cell units, relative to the grid origin.
  const double gx0 = (x - r - x0) / cell, gx1 = (x + r - x0) / cell;
  const double gy0 = (y - r - y0) / cell, gy1 = (y + r - y0) / cell;
  for (int j = j0; j <= j1; ++j)
    for (int i = i0; i <= i1; ++i) {
      if (!hasCell(i, j)) continue;
      const double z00 = at(i, j), z10 = at(i + 1, j), z01 = at(i, j + 1), z11 = at(i + 1, j + 1);
      // Planes of the triangles (p00, p10, p11) and (p00, p11, p01) in cell coordinates u, v.
      const double a1 = z10 - z00, b1 = z11 - z10, a2 = z11 - z01, b2 = z01 - z00;
      const double u0 = std::clamp(gx0 - i, 0.0, 1.0), u1 = std::clamp(gx1 - i, 0.0, 1.0);
      const double v0 = std::clamp(gy0 - j, 0.0, 1.0), v1 = std::clamp(gy1 - j, 0.0, 1.0);
      const double u = a1 > 0 ? u1 : u0, v = b1 > 0 ? v1 : v0;  // each plane's highest corner
      const double uu = a2 > 0 ? u1 : u0, vv = b2 > 0 ? v1 : v0;
      // An extended plane can rise above the cell's samples where the other triangle lies;
      // the surface over the cell never does.
      const double samples = std::max(std::max(z00, z10), std::max(z01, z11));
      top = std::max(top,
                     std::min(samples, std::max(z00 + u * a1 + v * b1, z00 + vv * b2 + uu * a2)));
    }
  return top + 1e-9;
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

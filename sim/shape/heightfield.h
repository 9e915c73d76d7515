// Terrain on a regular XY grid (example 6, fig. 18): the paper's "real terrain data" future
// work. Heights are samples on a grid; each grid cell is two triangles. Collision looks up the
// cells under a sphere directly from its x, y (no scan of all cells), which is what makes
// terrain lookup fast in the paper.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "sim/core/math.h"
#include "sim/geometry/cell_grid.h"
#include "sim/geometry/tri_mesh.h"

namespace vf {

struct Heightfield {
  int nx = 0, ny = 0;         // samples along x (columns) and y (rows), at least 2 each
  double x0 = 0, y0 = 0;      // position of sample (0, 0), the south-west one, m
  double cell = 1;            // sample spacing, m
  std::vector<double> z;      // nx * ny heights, z[j * nx + i] for sample (i, j); NaN = no data
  double zMin = 0, zMax = 0;  // over the samples with data
  // Georeference kept for outputs (GeoJSON paths, rasters): the source's coordinate reference
  // system as WKT (empty when the file has none), and the shift added to the file's
  // coordinates to get world coordinates (a scene may move a DEM near the origin).
  std::string crsWkt;
  std::string crsName;  // "AUTHORITY:CODE" (e.g. "EPSG:31287") when the CRS has one, else empty
  Vec3 shift = Vec3::Zero();

  double at(int i, int j) const { return z[static_cast<std::size_t>(j) * nx + i]; }
  // True if all four corners of cell (i, j) (samples i..i+1, j..j+1) have data.
  bool hasCell(int i, int j) const {
    return i >= 0 && j >= 0 && i + 1 < nx && j + 1 < ny && !std::isnan(at(i, j)) &&
           !std::isnan(at(i + 1, j)) && !std::isnan(at(i, j + 1)) && !std::isnan(at(i + 1, j + 1));
  }
  // Height of the triangulated surface at (x, y); NaN outside the grid or over missing data.
  double heightAt(double x, double y) const {
    const double gx = (x - x0) / cell, gy = (y - y0) / cell;
    if (!(gx >= 0 && gy >= 0 && gx <= nx - 1 && gy <= ny - 1))
      return std::numeric_limits<double>::quiet_NaN();
    // The far edge of the grid belongs to the last cell.
    const int i = cellIndex(gx, nx - 2), j = cellIndex(gy, ny - 2);
    if (!hasCell(i, j)) return std::numeric_limits<double>::quiet_NaN();
    const double u = gx - i, v = gy - j;
    const double z00 = at(i, j), z10 = at(i + 1, j), z01 = at(i, j + 1), z11 = at(i + 1, j + 1);
    if (u >= v) return z00 + u * (z10 - z00) + v * (z11 - z10);  // triangle (p00, p10, p11)
    return z00 + v * (z01 - z00) + u * (z11 - z01);              // triangle (p00, p11, p01)
  }
  // Upward unit normal of the surface triangle under (x, y); +z where heightAt is NaN.
  Vec3 normalAt(double x, double y) const;
  // The least z of normalAt over the cells with data that meet [x - r, x + r] x [y - r, y + r]
  // (the same values, bit for bit), and at most 1: normalAt's z anywhere in the square is no
  // less.
  double minNormalZNear(double x, double y, double r) const;
  // The cells whose squares meet [x - r, x + r] x [y - r, y + r], clamped to the grid:
  // i in [i0, i1], j in [j0, j1]; empty (i0 > i1 or j0 > j1) when the square misses the grid.
  void cellRange(double x, double y, double r, int& i0, int& i1, int& j0, int& j1) const {
    const Square s = square(x, y, r);
    cellRange(s, i0, i1, j0, j1);
  }
  // The highest sample of the cells that meet [x - r, x + r] x [y - r, y + r] (the surface
  // there is no higher); -infinity when the square misses the grid or has no data.
  double maxHeightNear(double x, double y, double r) const;
  // An upper bound of the triangulated surface over [x - r, x + r] x [y - r, y + r], m, much
  // tighter than maxHeightNear on slopes: per cell with data, the larger of the planes of its
  // triangles that the square reaches, at the corners of the part of the square over that cell
  // (a linear function's maximum over a rectangle is at a corner), capped by the cell's highest
  // sample, plus 1e-9 m against rounding; -infinity when the square meets no cell with data.
  double surfaceBoundNear(double x, double y, double r) const {
    bool clear;
    return scanNear<false>(Vec3(x, y, 0), r, clear);
  }
  // surfaceBoundNear(c.x, c.y, r), and in `clear` whether the sphere of radius r about c lies
  // on the upper side of the plane of every triangle that the square reaches, more than r (plus
  // 1e-9 m against rounding) from it, or above the highest sample of the triangle's cell. Then no
  // point of the surface, and no point of the border wall (which lies below the surface line of a
  // border triangle, which the square reaches wherever it reaches the border), is within r of
  // c, and c is above the surface: the sphere touches nothing there. On a slope this decides where
  // the bound cannot: the plane's maximum over the square lies above the sphere's lowest point
  // unless the sphere is 1 + |gradient| radii above the plane (measured vertically), while its
  // distance to the plane needs sqrt(1 + |gradient|^2). Squares that miss the grid, and cells
  // without data, are clear.
  double surfaceBoundNear(const Vec3& c, double r, bool& clear) const {
    return scanNear<true>(c, r, clear);
  }
  // True when the sphere of radius r about c lies strictly above the surface: no point of a
  // triangle under its footprint square within r (1e-9 relative and 1e-9 m allowed for
  // rounding) and its centre above. It then touches neither the surface nor the border wall.
  // The exact form of surfaceBoundNear's plane test, and dearer. May answer false for a sphere
  // that is above (never true for one that is not): when its square reaches the grid's
  // border or a cell without data, and when its centre is within r of the plane of the
  // triangle under it (a cheap first answer, right for nearly every node near the surface).
  bool sphereAbove(const Vec3& c, double r) const;
  // The surface height that a body whose lowest point is at `bottom` rests on when its points
  // `pts` (world) are lowered straight down until the first touches the surface:
  // bottom - min over pts of (p.z - heightAt(p.x, p.y)). Points over no data are skipped;
  // -infinity when all are. This is the surface directly under the body (drop_height).
  double surfaceUnder(const std::vector<Vec3>& pts, double bottom) const;
  // The two triangles of cell (i, j): (p00, p10, p11) and (p00, p11, p01), counter-clockwise
  // seen from above.
  void cellTriangles(int i, int j, Vec3 tri[2][3]) const;
  // All cells with data as a triangle mesh (for drawing; open, so never a body).
  TriMesh toMesh() const;

 private:
  // The cells under the square about c's x, y: the bound, and with kPlanes the plane test
  // (surfaceBoundNear above).
  template <bool kPlanes>
  double scanNear(const Vec3& c, double r, bool& clear) const {
    const Square s = square(c.x(), c.y(), r);
    int i0, i1, j0, j1;
    cellRange(s, i0, i1, j0, j1);
    double top = -INFINITY;
    clear = true;
    const double bottom = c.z() - r - 1e-9;
    const double r2 = r * r;
    const double gx = (c.x() - x0) / cell, gy = (c.y() - y0) / cell;  // c in cell units
    for (int j = j0; j <= j1; ++j) {  // cellRange keeps i + 1 < nx and j + 1 < ny
      const double* row0 = z.data() + static_cast<std::size_t>(j) * nx;
      const double* row1 = row0 + nx;
      const double v0 = std::clamp(s.gy0 - j, 0.0, 1.0), v1 = std::clamp(s.gy1 - j, 0.0, 1.0);
      for (int i = i0; i <= i1; ++i) {
        const double z00 = row0[i], z10 = row0[i + 1], z01 = row1[i], z11 = row1[i + 1];
        if (std::isnan(z00) || std::isnan(z10) || std::isnan(z01) || std::isnan(z11)) continue;
        const double samples = std::max(std::max(z00, z10), std::max(z01, z11));
        // Planes of the triangles (p00, p10, p11) and (p00, p11, p01) in cell coordinates u, v:
        // z = z00 + a1 u + b1 v and z = z00 + a2 u + b2 v.
        const double a1 = z10 - z00, b1 = z11 - z10, a2 = z11 - z01, b2 = z01 - z00;
        // The part of the square over the cell, [u0, u1] x [v0, v1], reaches the first
        // triangle (u >= v) when u1 >= v0 and the second (u <= v) when v1 >= u0; at least one.
        // A triangle it does not reach is no part of the surface under the square.
        const double u0 = std::clamp(s.gx0 - i, 0.0, 1.0), u1 = std::clamp(s.gx1 - i, 0.0, 1.0);
        const bool reaches1 = u1 >= v0, reaches2 = v1 >= u0;
        if (kPlanes && clear && bottom <= samples) {
          // c is more than r from a plane when its height d above it, less the margin, is
          // (fartherAbove).
          const double u = gx - i, v = gy - j;
          const double d1 = c.z() - (z00 + u * a1 + v * b1) - 1e-9;
          const double d2 = c.z() - (z00 + v * b2 + u * a2) - 1e-9;
          clear = (!reaches1 || fartherAbove(d1, a1, b1, r2)) &&
                  (!reaches2 || fartherAbove(d2, a2, b2, r2));
        }
        // An extended plane can rise above the cell's samples where the other triangle lies;
        // the surface over the cell never does. A cell whose samples are no higher than the
        // bound so far cannot raise it.
        if (samples <= top) continue;
        const double u = a1 > 0 ? u1 : u0, v = b1 > 0 ? v1 : v0;  // each plane's highest corner
        const double uu = a2 > 0 ? u1 : u0, vv = b2 > 0 ? v1 : v0;
        const double high1 = reaches1 ? z00 + u * a1 + v * b1 : -INFINITY;
        const double high2 = reaches2 ? z00 + vv * b2 + uu * a2 : -INFINITY;
        top = std::max(top, std::min(samples, std::max(high1, high2)));
      }
    }
    return top + 1e-9;
  }
  // Whether a point at height d above the plane z = z00 + a u + b v of a cell (u, v in cell
  // units) lies above it and farther than sqrt(r2) from it: d > 0 and
  // d^2 > r2 (1 + (a^2 + b^2) / cell^2).
  bool fartherAbove(double d, double a, double b, double r2) const {
    return d > 0 && d * d * (cell * cell) > r2 * (cell * cell + a * a + b * b);
  }
  // The square [x - r, x + r] x [y - r, y + r] relative to the grid origin, in m (o*) and in
  // cell units (g*): the cell range and the pruning bound share the divisions.
  struct Square {
    double ox0, ox1, oy0, oy1;
    double gx0, gx1, gy0, gy1;
  };
  Square square(double x, double y, double r) const {
    Square s;
    s.ox0 = x - r - x0, s.ox1 = x + r - x0, s.oy0 = y - r - y0, s.oy1 = y + r - y0;
    s.gx0 = s.ox0 / cell, s.gx1 = s.ox1 / cell, s.gy0 = s.oy0 / cell, s.gy1 = s.oy1 / cell;
    return s;
  }
  void cellRange(const Square& s, int& i0, int& i1, int& j0, int& j1) const {
    if (s.ox1 < 0 || s.oy1 < 0 || s.ox0 > (nx - 1) * cell || s.oy0 > (ny - 1) * cell) {
      i0 = j0 = 0;
      i1 = j1 = -1;
      return;
    }
    i0 = cellIndex(s.gx0, nx - 2);
    i1 = cellIndex(s.gx1, nx - 2);
    j0 = cellIndex(s.gy0, ny - 2);
    j1 = cellIndex(s.gy1, ny - 2);
  }
};

// Reads a DEM in any raster format GDAL reads (GeoTIFF, ESRI ASCII with xllcorner or
// xllcenter, ...): band 1, heights in metres, NODATA cells become NaN. Samples sit at the
// pixel centres; the raster must be north-up with square cells. Keeps the CRS. Throws
// InputError naming the file and GDAL's reason, or a raster of more than kMaxDemSamples
// samples. (sim/shape/dem_import.cpp: the only GDAL include.)
Heightfield loadDem(const std::string& path);
// The most samples a DEM may have: 2^28 (16,384 x 16,384; 2 GiB of heights), far below what
// 32-bit sample indices allow; larger grids are cropped or resampled first.
inline constexpr std::int64_t kMaxDemSamples = std::int64_t{1} << 28;

// The world position of a point given in the DEM file's coordinates, and back.
inline Vec3 demToWorld(const Heightfield& h, const Vec3& p) { return p + h.shift; }
inline Vec3 worldToDem(const Heightfield& h, const Vec3& p) { return p - h.shift; }

// Moves the grid by `shift` (world = file coordinates + shift), keeping the record of it.
void shiftHeightfield(Heightfield& h, const Vec3& shift);

}  // namespace vf

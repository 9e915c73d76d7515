// Terrain on a regular XY grid (example 6, fig. 18): the paper's "real terrain data" future
// work. Heights are samples on a grid; each grid cell is two triangles. Collision looks up the
// cells under a sphere directly from its x, y (no scan of all cells), which is what makes
// terrain lookup fast in the paper.
#pragma once

#include <string>
#include <vector>

#include "sim/core/math.h"
#include "sim/geometry/tri_mesh.h"

namespace vf {

struct Heightfield {
  int nx = 0, ny = 0;         // samples along x (columns) and y (rows)
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
  bool hasCell(int i, int j) const;
  // Height of the triangulated surface at (x, y); NaN outside the grid or over missing data.
  double heightAt(double x, double y) const;
  // Upward unit normal of the surface triangle under (x, y); +z where heightAt is NaN.
  Vec3 normalAt(double x, double y) const;
  // The cells whose squares meet [x - r, x + r] x [y - r, y + r], clamped to the grid:
  // i in [i0, i1], j in [j0, j1]; empty (i0 > i1 or j0 > j1) when the square misses the grid.
  void cellRange(double x, double y, double r, int& i0, int& i1, int& j0, int& j1) const;
  // The highest sample of the cells that meet [x - r, x + r] x [y - r, y + r] (the surface
  // there is no higher); -infinity when the square misses the grid or has no data.
  double maxHeightNear(double x, double y, double r) const;
  // An upper bound of the triangulated surface over [x - r, x + r] x [y - r, y + r], m, much
  // tighter than maxHeightNear on slopes: per cell with data, the larger of its two triangles'
  // planes at the corners of the part of the square over that cell (a linear function's
  // maximum over a rectangle is at a corner), capped by the cell's highest sample, plus 1e-9 m
  // against rounding; -infinity when the square meets no cell with data.
  double surfaceBoundNear(double x, double y, double r) const;
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
};

// Reads a DEM in any raster format GDAL reads (GeoTIFF, ESRI ASCII with xllcorner or
// xllcenter, ...): band 1, heights in metres, NODATA cells become NaN. Samples sit at the
// pixel centres; the raster must be north-up with square cells. Keeps the CRS. Throws
// InputError naming the file and GDAL's reason. (sim/shape/dem_import.cpp: the only GDAL
// include.)
Heightfield loadDem(const std::string& path);

// The world position of a point given in the DEM file's coordinates, and back.
inline Vec3 demToWorld(const Heightfield& h, const Vec3& p) { return p + h.shift; }
inline Vec3 worldToDem(const Heightfield& h, const Vec3& p) { return p - h.shift; }

// Moves the grid by `shift` (world = file coordinates + shift), keeping the record of it.
void shiftHeightfield(Heightfield& h, const Vec3& shift);

}  // namespace vf

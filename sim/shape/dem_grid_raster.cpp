// Rasters onto a DEM's grid through gdalwarp (as a library call): checked for a georeference, a
// CRS that agrees with the DEM's and an extent that covers it, then warped into an in-memory
// dataset of exactly the DEM's samples and read back bottom row first.
#include "sim/shape/dem_grid_raster.h"

#include <gdal.h>
#include <gdal_utils.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <mutex>

#include "sim/core/error.h"
#include "sim/shape/crs.h"
#include "sim/shape/gdal_support.h"

namespace vf {
namespace {

// The bounding box of the raster's cells in its own coordinates (any geotransform).
gdal::Extent rasterExtent(GDALDatasetH ds, const double gt[6]) {
  const int w = GDALGetRasterXSize(ds), h = GDALGetRasterYSize(ds);
  gdal::Extent e{INFINITY, INFINITY, -INFINITY, -INFINITY};
  for (int cx : {0, w})
    for (int cy : {0, h}) {
      const double x = gt[0] + cx * gt[1] + cy * gt[2], y = gt[3] + cx * gt[4] + cy * gt[5];
      e.x0 = std::min(e.x0, x), e.x1 = std::max(e.x1, x);
      e.y0 = std::min(e.y0, y), e.y1 = std::max(e.y1, y);
    }
  return e;
}

std::string describe(const gdal::Extent& e) {
  char buf[160];
  std::snprintf(buf, sizeof buf, "x %.3f .. %.3f, y %.3f .. %.3f", e.x0, e.x1, e.y0, e.y1);
  return buf;
}

// gdalwarp of `src` onto exactly the DEM's samples (its cells' extent, nx x ny pixels), Float64,
// NaN where the source has no data or does not reach.
GDALDatasetH warpOntoSamples(GDALDatasetH src, const Heightfield& dem, GridResampling r) {
  const gdal::Extent e = gdal::demExtent(dem);
  char bounds[4][32];
  for (int k = 0; k < 4; ++k)  // %.17g: the DEM's own coordinates to the last bit
    std::snprintf(bounds[k], sizeof bounds[k], "%.17g",
                  k == 0   ? e.x0
                  : k == 1 ? e.y0
                  : k == 2 ? e.x1
                           : e.y1);
  const std::vector<std::string> args = {"-of",
                                         "MEM",
                                         "-ot",
                                         "Float64",
                                         "-r",
                                         r == GridResampling::kNearest ? "near" : "bilinear",
                                         "-dstnodata",
                                         "nan",
                                         "-te",
                                         bounds[0],
                                         bounds[1],
                                         bounds[2],
                                         bounds[3],
                                         "-ts",
                                         std::to_string(dem.nx),
                                         std::to_string(dem.ny)};
  return gdal::runUtility<GDALWarpAppOptions>(
      args, GDALWarpAppOptionsNew,
      [&](GDALWarpAppOptions* o, int* err) { return GDALWarp("", nullptr, 1, &src, o, err); },
      GDALWarpAppOptionsFree);
}

}  // namespace

std::vector<double> loadOnDemGrid(const std::string& path, const Heightfield& dem,
                                  GridResampling resampling, const std::string& what) {
  static std::once_flag registered;
  std::call_once(registered, [] { GDALAllRegister(); });
  gdal::QuietErrors errors;
  gdal::Dataset src;
  src.h = GDALOpenEx(path.c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY, nullptr, nullptr, nullptr);
  if (!src.h) throw InputError(path, "cannot read the " + what + " raster: " + errors.last());
  if (GDALGetRasterCount(src.h) < 1) throw InputError(path, what + " raster has no band");
  double gt[6];
  if (GDALGetGeoTransform(src.h, gt) != CE_None)
    throw InputError(path, what +
                               " raster has no georeference (geotransform): it cannot be "
                               "placed on the DEM");
  const std::string wkt = GDALGetProjectionRef(src.h) ? GDALGetProjectionRef(src.h) : "";
  if (crsConflict(wkt, dem.crsWkt))
    throw InputError(path, what + " raster is in " + crsLabel(wkt) + ", the DEM in " +
                               crsLabel(dem.crsWkt) +
                               "; give the raster in the DEM's CRS (e.g. gdalwarp -t_srs)");
  const gdal::Extent need = gdal::demExtent(dem), have = rasterExtent(src.h, gt);
  const double tolerance = 1e-6 * dem.cell;
  if (have.x0 > need.x0 + tolerance || have.y0 > need.y0 + tolerance ||
      have.x1 < need.x1 - tolerance || have.y1 < need.y1 - tolerance)
    throw InputError(path, what + " raster does not cover the DEM: it covers " + describe(have) +
                               ", the DEM " + describe(need));
  gdal::Dataset warped;
  warped.h = warpOntoSamples(src.h, dem, resampling);
  if (!warped.h)
    throw InputError(
        path, "cannot resample the " + what + " raster onto the DEM's grid: " + errors.last());
  std::vector<double> v(static_cast<std::size_t>(dem.nx) * dem.ny, NAN);
  // GDAL's rows run from the north, ours from the south: the last row first, stepping back.
  double* last = v.data() + static_cast<std::size_t>(dem.ny - 1) * dem.nx;
  const GSpacing line = -static_cast<GSpacing>(sizeof(double)) * dem.nx;
  if (GDALRasterIOEx(GDALGetRasterBand(warped.h, 1), GF_Read, 0, 0, dem.nx, dem.ny, last, dem.nx,
                     dem.ny, GDT_Float64, sizeof(double), line, nullptr) != CE_None)
    throw InputError(path, "cannot read the " + what + " raster's values: " + errors.last());
  for (double& x : v)
    if (!std::isfinite(x)) x = NAN;
  return v;
}

}  // namespace vf

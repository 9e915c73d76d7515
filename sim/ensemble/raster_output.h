// Per-cell rasters out through GDAL, on the grid, georeference and CRS of the input DEM.
// (sim/ensemble/raster_output.cpp: with dem_import.cpp, the only GDAL includes.)
#pragma once

#include <string>
#include <vector>

namespace vf {

enum class RasterFormat { kGeoTiff, kEsriAscii };

// NODATA value written for NaN (ESRI ASCII grids need a number; GeoTIFF gets the same).
inline constexpr double kRasterNoData = -9999.0;

// Writes `values` (nx * ny, Heightfield::z's layout: j from the south; NaN = no data) to
// `path` as a Float64 raster whose geotransform is copied from the DEM file `demPath` (read from
// the file itself, so it equals the input's exactly) and whose CRS is `crsWkt` (the DEM's own,
// or the one the scene gave it; empty: none). `path` is written in place
// (callers pass an OutputFile's temporary path and rename it). ESRI ASCII holds no CRS: GDAL's
// ESRI-flavoured .prj sidecar, which drops parts of some CRSs (the datum shift of EPSG:31287),
// is removed; callers write the DEM's own WKT as the .prj (Heightfield::crsWkt). Throws
// InputError naming `path` with GDAL's reason.
void writeRaster(const std::string& path, RasterFormat format, const std::vector<double>& values,
                 int nx, int ny, const std::string& demPath, const std::string& crsWkt);

}  // namespace vf

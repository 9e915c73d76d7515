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
// `path` as a Float64 raster whose geotransform and CRS are copied from the DEM file `demPath`
// (read from the file itself, so they equal the input's exactly). `path` is written in place
// (callers pass an OutputFile's temporary path and rename it). For ESRI ASCII with a CRS, GDAL
// also writes the CRS beside it as PATH-STEM.prj: that path is returned, "" otherwise. Throws
// InputError naming `path` with GDAL's reason.
std::string writeRaster(const std::string& path, RasterFormat format,
                        const std::vector<double>& values, int nx, int ny,
                        const std::string& demPath);

}  // namespace vf

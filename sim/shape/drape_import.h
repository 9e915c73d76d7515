// A picture draped on a terrain (`[ground] texture`): any raster GDAL reads, an orthophoto
// most often, resampled over the DEM's extent so the renderer can map a world point to its
// texel with two numbers per axis. GDAL does the reading, reprojecting and resampling
// (sim/shape/drape_import.cpp); this header holds no GDAL type.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "sim/shape/heightfield.h"

namespace vf {

struct DrapeImage {
  int width = 0, height = 0;
  // 8-bit sRGB-encoded red, green, blue and coverage (alpha: 0 where the raster has no data
  // or does not reach), row 0 along the southern edge, row-major.
  std::vector<std::uint8_t> rgba;
  // The world rectangle the image covers: the DEM raster's extent (the outer edges of its
  // cells, half a cell outside the outermost samples), m.
  double x0 = 0, y0 = 0, x1 = 0, y1 = 0;
};

// The longest side of a drape, texels: a 4096 x 4096 RGBA texture is 64 MiB, and finer
// texels than that over a whole DEM are smaller than a pixel in any frame that shows it.
inline constexpr int kMaxDrapeSide = 4096;

// Reads `path` and resamples it (bilinear) over the extent of terrain `h`. A georeferenced
// raster is placed by its geotransform (reprojected to the DEM's CRS when both have one and
// they differ) at its own resolution, capped at kMaxDrapeSide; a raster without georeference
// is stretched over the DEM's extent. Bands: red, green, blue from the first three, one band
// as grey, a palette expanded; values are read as 8-bit. Throws InputError naming the file.
DrapeImage loadDrape(const std::string& path, const Heightfield& h);

}  // namespace vf

// A raster of values on a DEM's samples (a forest's stem density, DBH, species class): any raster
// GDAL reads, in the DEM's CRS or in none, at any resolution, resampled by GDAL (gdalwarp as a
// library call) onto the DEM's grid. This header holds no GDAL type.
#pragma once

#include <string>
#include <vector>

#include "sim/shape/heightfield.h"

namespace vf {

enum class GridResampling {
  kBilinear,  // quantities (density, diameter): bilinear between the raster's own cells
  kNearest,   // classes: the value of the nearest cell, never a blend of two classes
};

// The values of `path` (first band) at the samples of `dem`, z[j * nx + i] order (row 0 the
// southern); NaN where the raster has no data. `what` names the raster in messages ("stem
// density"). Throws InputError naming the file when GDAL cannot read it, when it has no
// georeference, when its CRS and the DEM's are both tied to the Earth and differ (it is not
// reprojected: give it in the DEM's CRS), or when it does not cover the DEM's extent.
std::vector<double> loadOnDemGrid(const std::string& path, const Heightfield& dem,
                                  GridResampling resampling, const std::string& what);

}  // namespace vf

// A point file of trees (any vector format OGR reads: GeoPackage, shapefile, GeoJSON, CSV with
// geometry) turned into a stand on a DEM's samples: per sample's cell, the stems standing in it
// as a density and their mean DBH. This header holds no GDAL type.
#pragma once

#include <string>
#include <vector>

#include "sim/shape/heightfield.h"

namespace vf {

struct TreeStand {
  std::vector<double> density;  // stems/ha per sample: the trees in its cell / the cell's area
  std::vector<double> dbh;      // cm, their mean DBH; 0 where the cell has none
  int trees = 0;                // trees that stand on the grid (others are left out)
};

// Reads the point features of `path`'s first layer, each with a numeric field `dbhField` (cm),
// in the DEM's CRS or in none, and counts each tree in the cell of the DEM sample nearest to it
// (trees beyond the grid's cells are left out). Throws InputError naming the file when OGR cannot
// read it, its CRS conflicts with the DEM's, it has no field `dbhField`, a feature is not a point
// or has a negative or missing DBH (naming the feature), or no tree stands on the grid.
TreeStand loadTreePoints(const std::string& path, const std::string& dbhField,
                         const Heightfield& dem);

}  // namespace vf

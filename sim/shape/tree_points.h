// A point file of trees (any vector format OGR reads: GeoPackage, shapefile, GeoJSON), read by
// the shared vector reader (vector_import.h) into the DEM's CRS and turned into a stand on the
// DEM's samples: per sample's cell, the stems standing in it as a density and their mean DBH.
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
// transformed into the DEM's CRS, and counts each tree in the cell of the DEM sample nearest to
// it (trees beyond the grid's cells are left out). Throws InputError naming the file for what
// readVectorFile refuses (a missing file, no CRS on either side, ...), a feature that is not a
// point or has no or a negative DBH (naming the feature), or no tree on the grid.
TreeStand loadTreePoints(const std::string& path, const std::string& dbhField,
                         const Heightfield& dem);

}  // namespace vf

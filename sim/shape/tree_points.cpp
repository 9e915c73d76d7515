// Tree points onto the DEM's samples (see tree_points.h).
#include "sim/shape/tree_points.h"

#include <cmath>

#include "sim/core/error.h"
#include "sim/shape/vector_import.h"

namespace vf {

TreeStand loadTreePoints(const std::string& path, const std::string& dbhField,
                         const Heightfield& dem) {
  TreeStand stand;
  const std::size_t n = static_cast<std::size_t>(dem.nx) * dem.ny;
  stand.density.assign(n, 0.0);
  stand.dbh.assign(n, 0.0);
  const double west = dem.x0 - dem.shift.x(), south = dem.y0 - dem.shift.y();  // file coords
  for (const VectorFeature& f : readVectorFile(path, dem.crsWkt)) {
    const std::string id = "feature " + std::to_string(f.id);
    if (f.kind != VectorFeature::Kind::kPoint)
      throw InputError(path, id + " is not a point; a tree is a point at its stem");
    const std::optional<double> dbh = f.number(dbhField);
    if (!dbh)
      throw InputError(path, id + " has no DBH: no numeric field '" + dbhField +
                                 "' (the DBH in cm; name another with 'trees_dbh_field')");
    if (!(*dbh >= 0) || !std::isfinite(*dbh))
      throw InputError(path, id + " has DBH " + std::to_string(*dbh) + " cm: it must be >= 0");
    const std::array<double, 2>& p = f.rings.front().front();
    const long i = std::lround((p[0] - west) / dem.cell),
               j = std::lround((p[1] - south) / dem.cell);
    if (i < 0 || j < 0 || i >= dem.nx || j >= dem.ny) continue;
    const std::size_t k = static_cast<std::size_t>(j) * dem.nx + static_cast<std::size_t>(i);
    stand.density[k] += 1;
    stand.dbh[k] += *dbh;
    ++stand.trees;
  }
  if (stand.trees == 0) throw InputError(path, "no tree of the point file stands on the DEM");
  const double cellHectares = dem.cell * dem.cell / 1e4;
  for (std::size_t k = 0; k < n; ++k)
    if (stand.density[k] > 0) {
      stand.dbh[k] /= stand.density[k];  // the mean of the cell's trees
      stand.density[k] /= cellHectares;
    }
  return stand;
}

}  // namespace vf

// Tree points through OGR's C API onto the DEM's samples (see tree_points.h).
#include "sim/shape/tree_points.h"

#include <cpl_conv.h>
#include <gdal.h>
#include <ogr_api.h>

#include <cmath>
#include <mutex>

#include "sim/core/error.h"
#include "sim/shape/crs.h"
#include "sim/shape/gdal_support.h"

namespace vf {
namespace {

struct FeatureDeleter {
  void operator()(OGRFeatureH f) const { OGR_F_Destroy(f); }
};
using Feature = std::unique_ptr<std::remove_pointer_t<OGRFeatureH>, FeatureDeleter>;

std::string layerWkt(OGRLayerH layer) {
  OGRSpatialReferenceH srs = OGR_L_GetSpatialRef(layer);
  if (!srs) return "";
  char* wkt = nullptr;
  std::string out;
  if (OSRExportToWkt(srs, &wkt) == OGRERR_NONE && wkt) out = wkt;
  CPLFree(wkt);
  return out;
}

}  // namespace

TreeStand loadTreePoints(const std::string& path, const std::string& dbhField,
                         const Heightfield& dem) {
  static std::once_flag registered;
  std::call_once(registered, [] { GDALAllRegister(); });
  gdal::QuietErrors errors;
  gdal::Dataset src;
  src.h = GDALOpenEx(path.c_str(), GDAL_OF_VECTOR | GDAL_OF_READONLY, nullptr, nullptr, nullptr);
  if (!src.h) throw InputError(path, "cannot read the tree point file: " + errors.last());
  OGRLayerH layer = GDALDatasetGetLayerCount(src.h) > 0 ? GDALDatasetGetLayer(src.h, 0) : nullptr;
  if (!layer) throw InputError(path, "tree point file has no layer");
  const std::string wkt = layerWkt(layer);
  if (crsConflict(wkt, dem.crsWkt))
    throw InputError(path, "tree point file is in " + crsLabel(wkt) + ", the DEM in " +
                               crsLabel(dem.crsWkt) +
                               "; give the points in the DEM's CRS (e.g. ogr2ogr -t_srs)");
  const int field = OGR_FD_GetFieldIndex(OGR_L_GetLayerDefn(layer), dbhField.c_str());
  if (field < 0)
    throw InputError(path, "tree point file has no field '" + dbhField +
                               "' (the DBH in cm; name another with 'trees_dbh_field')");
  TreeStand stand;
  const std::size_t n = static_cast<std::size_t>(dem.nx) * dem.ny;
  stand.density.assign(n, 0.0);
  stand.dbh.assign(n, 0.0);
  const double west = dem.x0 - dem.shift.x(), south = dem.y0 - dem.shift.y();  // file coords
  OGR_L_ResetReading(layer);
  for (Feature f(OGR_L_GetNextFeature(layer)); f; f.reset(OGR_L_GetNextFeature(layer))) {
    const std::string id = "feature " + std::to_string(OGR_F_GetFID(f.get()));
    OGRGeometryH g = OGR_F_GetGeometryRef(f.get());
    if (!g || wkbFlatten(OGR_G_GetGeometryType(g)) != wkbPoint)
      throw InputError(path, id + " is not a point; a tree is a point at its stem");
    if (!OGR_F_IsFieldSetAndNotNull(f.get(), field))
      throw InputError(path, id + " has no DBH ('" + dbhField + "')");
    const double dbh = OGR_F_GetFieldAsDouble(f.get(), field);
    if (!(dbh >= 0) || !std::isfinite(dbh))
      throw InputError(path, id + " has DBH " + std::to_string(dbh) + " cm: it must be >= 0");
    const long i = std::lround((OGR_G_GetX(g, 0) - west) / dem.cell);
    const long j = std::lround((OGR_G_GetY(g, 0) - south) / dem.cell);
    if (i < 0 || j < 0 || i >= dem.nx || j >= dem.ny) continue;
    const std::size_t k = static_cast<std::size_t>(j) * dem.nx + static_cast<std::size_t>(i);
    stand.density[k] += 1;
    stand.dbh[k] += dbh;
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

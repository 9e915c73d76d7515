// DEM coordinates -> WGS84 through GDAL's OGRCoordinateTransformation (the C API of it).
#include "sim/shape/geo_location.h"

#include <ogr_srs_api.h>

#include <cmath>
#include <memory>
#include <numbers>

#include "sim/core/error.h"
#include "sim/shape/gdal_support.h"

namespace vf {
namespace {

using gdal::Srs;

struct TransformDeleter {
  void operator()(OGRCoordinateTransformationH h) const { OCTDestroyCoordinateTransformation(h); }
};
using Transform =
    std::unique_ptr<std::remove_pointer_t<OGRCoordinateTransformationH>, TransformDeleter>;

// x, y in the traditional GIS order (easting or longitude first) whatever the CRS's authority
// says: GDAL 3 otherwise swaps the axes of EPSG:4326 to latitude first.
Srs traditional(OGRSpatialReferenceH h) {
  Srs srs(h);
  if (srs) OSRSetAxisMappingStrategy(srs.get(), OAMS_TRADITIONAL_GIS_ORDER);
  return srs;
}

}  // namespace

GeoLocation geoLocation(const Heightfield& h, const Vec3& p, const std::string& where) {
  if (h.crsWkt.empty())
    throw InputError(where,
                     "the sun of a date and time needs the terrain's place on the Earth, and the "
                     "DEM has no coordinate reference system; give [light] 'azimuth' and "
                     "'elevation' instead, or a georeferenced DEM (e.g. a GeoTIFF with its CRS)");
  gdal::QuietErrors errors;
  Srs grid = traditional(OSRNewSpatialReference(h.crsWkt.c_str()));
  Srs wgs84 = traditional(OSRNewSpatialReference(nullptr));
  if (!grid || !wgs84 || OSRSetWellKnownGeogCS(wgs84.get(), "WGS84") != OGRERR_NONE)
    throw InputError(where, "cannot read the DEM's coordinate reference system: " + errors.last());
  // A local engineering CRS (what GDAL reads from an ESRI grid without a .prj) names no place.
  if (!OSRIsProjected(grid.get()) && !OSRIsGeographic(grid.get()))
    throw InputError(where,
                     "the sun of a date and time needs the terrain's place on the Earth, and the "
                     "DEM's coordinate reference system is a local one, not tied to the Earth; "
                     "give [light] 'azimuth' and 'elevation' instead, or a DEM with a projected "
                     "or geographic CRS");
  Transform toWgs84(OCTNewCoordinateTransformation(grid.get(), wgs84.get()));
  Transform toGrid(OCTNewCoordinateTransformation(wgs84.get(), grid.get()));
  if (!toWgs84 || !toGrid)
    throw InputError(where, "cannot transform the DEM's coordinates to WGS84: " + errors.last());
  const Vec3 file = worldToDem(h, p);
  double x = file.x(), y = file.y(), z = 0;
  if (!OCTTransform(toWgs84.get(), 1, &x, &y, &z) || !std::isfinite(x) || !std::isfinite(y))
    throw InputError(where, "cannot transform the DEM's centre to WGS84: " + errors.last());
  GeoLocation g;
  g.longitudeDegrees = x;
  g.latitudeDegrees = y;
  // True north: the grid position of a point a little north of this one (0.001 degrees of
  // latitude, about 110 m: far above the transformation's rounding, small enough that the
  // meridian is straight over it). Near a pole, step south instead.
  const double step = y < 89 ? 1e-3 : -1e-3;
  double nx = x, ny = y + step, nz = 0;
  if (!OCTTransform(toGrid.get(), 1, &nx, &ny, &nz) || !std::isfinite(nx) || !std::isfinite(ny))
    throw InputError(where, "cannot transform WGS84 back to the DEM's grid: " + errors.last());
  const double sign = step > 0 ? 1 : -1;
  g.trueNorthDegrees =
      std::atan2(sign * (nx - file.x()), sign * (ny - file.y())) * 180 / std::numbers::pi;
  return g;
}

}  // namespace vf

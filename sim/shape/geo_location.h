// Where a terrain lies on the Earth: latitude and longitude (WGS84) of a point of a DEM that
// has a coordinate reference system, and where true north lies in its grid. The renderer's sun
// for a date and time needs both (render/light.cpp). GDAL's coordinate transformation does the
// work (sim/shape/geo_location.cpp).
#pragma once

#include <string>

#include "sim/core/math.h"
#include "sim/shape/heightfield.h"

namespace vf {

struct GeoLocation {
  double latitudeDegrees = 0;   // WGS84, north positive
  double longitudeDegrees = 0;  // WGS84, east positive
  // True north seen from the grid: degrees clockwise from the grid's north (+y). Projected
  // grids turn away from the meridians by the meridian convergence (up to a few degrees in a
  // UTM zone); 0 for a grid in longitude and latitude.
  double trueNorthDegrees = 0;
};

// The location of world point p of terrain h (world = the DEM file's coordinates + h.shift).
// Throws InputError naming `where` when the DEM has no CRS or GDAL cannot transform the point.
GeoLocation geoLocation(const Heightfield& h, const Vec3& p, const std::string& where);

}  // namespace vf

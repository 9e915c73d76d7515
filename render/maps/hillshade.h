// Hillshade of a DEM: the brightness of each sample's surface under a distant sun, the relief
// under a hazard map.
#pragma once

#include <vector>

#include "sim/shape/heightfield.h"

namespace vf {

// Where the sun stands: azimuth clockwise from north, altitude above the horizon, degrees. The
// defaults (315 deg, from the north-west; 45 deg) are the cartographic convention (light from
// the upper left of a north-up map) and those of GDAL's gdaldem and ESRI's Hillshade.
struct SunPosition {
  double azimuthDeg = 315;
  double altitudeDeg = 45;
};

// Hillshade in [0, 1] per sample (same layout as dem.z): cos(zenith) cos(slope) +
// sin(zenith) sin(slope) cos(azimuth - aspect), clamped at 0 (faces turned from the sun),
// with slope and aspect from Horn's (1981) 3 x 3 finite differences, heights unscaled (z
// factor 1). NaN where the sample has no data. A neighbour off the grid or without data takes
// the centre sample's height, so edges and holes are shaded from the neighbours that exist.
std::vector<double> hillshade(const Heightfield& dem, const SunPosition& sun = {});

// The same for sample (i, j) alone (0 <= i < nx, 0 <= j < ny): a map shades only the samples it
// shows, so its cost does not grow with the DEM.
double hillshadeAt(const Heightfield& dem, int i, int j, const SunPosition& sun = {});

}  // namespace vf

// Horn, B.K.P. (1981), "Hill shading and the reflectance map", Proc. IEEE 69(1): the gradient at
// a sample is the weighted difference of its 3 x 3 neighbourhood, the two neighbours in line
// weighted 2 and the diagonal ones 1, over 8 cell widths. It is exact on planes and smooths
// noise more than the 2-point difference; gdaldem and ESRI's Hillshade use it too.
#include "render/maps/hillshade.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace vf {

double hillshadeAt(const Heightfield& dem, int i, int j, const SunPosition& sun) {
  const double centre = dem.at(i, j);
  if (std::isnan(centre)) return centre;
  // Height of neighbour (i + di, j + dj); j grows to the north.
  const auto h = [&](int di, int dj) {
    const int a = i + di, b = j + dj;
    if (a < 0 || a >= dem.nx || b < 0 || b >= dem.ny) return centre;
    const double v = dem.at(a, b);
    return std::isnan(v) ? centre : v;
  };
  const double dzdx =
      ((h(1, 1) + 2 * h(1, 0) + h(1, -1)) - (h(-1, 1) + 2 * h(-1, 0) + h(-1, -1))) / (8 * dem.cell);
  const double dzdy =
      ((h(-1, 1) + 2 * h(0, 1) + h(1, 1)) - (h(-1, -1) + 2 * h(0, -1) + h(1, -1))) / (8 * dem.cell);
  const double slope = std::atan(std::hypot(dzdx, dzdy));
  // Aspect: the compass direction the slope faces (downhill, -gradient), clockwise from north:
  // atan2(east, north) of (-dzdx, -dzdy). Undefined on flat ground, where sin(slope) = 0
  // removes it.
  const double aspect = std::atan2(-dzdx, -dzdy);
  const double deg = std::numbers::pi / 180;
  const double zenith = (90 - sun.altitudeDeg) * deg, azimuth = sun.azimuthDeg * deg;
  const double s = std::cos(zenith) * std::cos(slope) +
                   std::sin(zenith) * std::sin(slope) * std::cos(azimuth - aspect);
  return std::max(0.0, s);
}

std::vector<double> hillshade(const Heightfield& dem, const SunPosition& sun) {
  std::vector<double> shade(dem.z.size());
  for (int j = 0; j < dem.ny; ++j)
    for (int i = 0; i < dem.nx; ++i)
      shade[static_cast<std::size_t>(j) * dem.nx + i] = hillshadeAt(dem, i, j, sun);
  return shade;
}

}  // namespace vf

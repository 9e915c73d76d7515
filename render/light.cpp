#include "render/light.h"

#include <cmath>
#include <cstdio>
#include <numbers>

#include "render/solar_position.h"
#include "sim/core/error.h"
#include "sim/shape/geo_location.h"
#include "sim/shape/heightfield.h"

namespace vf {
namespace {

constexpr double kDegrees = std::numbers::pi / 180;

// The default sun's place relative to the automatic camera (defaultSunDirection).
constexpr double kDefaultElevation = 45;
// Degrees counter-clockwise (seen from above) of the camera's azimuth: behind its right
// shoulder (the camera's right lies 90 degrees clockwise of its view, so 90 degrees
// counter-clockwise of the way back).
constexpr double kDefaultTurn = 30;

Vec3 rgb(const Color& c, double scale = 1) { return Vec3(c[0], c[1], c[2]) * scale; }

}  // namespace

Vec3 sunFromCompass(double azimuthDegrees, double elevationDegrees) {
  const double a = azimuthDegrees * kDegrees, e = elevationDegrees * kDegrees;
  return Vec3(std::cos(e) * std::sin(a), std::cos(e) * std::cos(a), std::sin(e));
}

Vec3 defaultSunDirection(const Vec3& view) {
  // Compass azimuth of the way back to the camera, turned counter-clockwise (a smaller compass
  // angle: towards the camera's right).
  const double back = std::atan2(-view.x(), -view.y()) / kDegrees;
  return sunFromCompass(back - kDefaultTurn, kDefaultElevation);
}

SceneLight sceneLight(const LightSpec& spec, const Heightfield* terrain) {
  SceneLight light;
  light.colors.sun = rgb(spec.color, spec.intensity);
  light.colors.sky = rgb(spec.sky);
  light.colors.ambient = rgb(spec.ambient);
  if (spec.azimuthDegrees && spec.elevationDegrees) {
    light.sunDirection = sunFromCompass(*spec.azimuthDegrees, *spec.elevationDegrees);
  } else if (spec.date) {
    if (!terrain)
      throw InputError(spec.where,
                       "'date' and 'time' place the sun for the terrain's location, and the "
                       "scene has no terrain; give 'azimuth' and 'elevation' instead");
    const Vec3 centre(terrain->x0 + 0.5 * (terrain->nx - 1) * terrain->cell,
                      terrain->y0 + 0.5 * (terrain->ny - 1) * terrain->cell, 0);
    const GeoLocation where = geoLocation(*terrain, centre, spec.where);
    const CivilDate& d = *spec.date;
    const SunPosition sun = sunPosition(d.year, d.month, d.day, spec.utcSeconds,
                                        where.latitudeDegrees, where.longitudeDegrees);
    if (!(sun.elevationDegrees > 0)) {
      char text[160];
      std::snprintf(text, sizeof text,
                    "the sun is %.1f degrees below the horizon at latitude %.4f, longitude %.4f "
                    "then; pick a time of day in UTC",
                    -sun.elevationDegrees, where.latitudeDegrees, where.longitudeDegrees);
      throw InputError(spec.where, text);
    }
    // A compass direction from true north is that much clockwise of true north, which lies
    // trueNorthDegrees clockwise of the grid's north.
    light.sunDirection =
        sunFromCompass(sun.azimuthDegrees + where.trueNorthDegrees, sun.elevationDegrees);
  }
  return light;
}

}  // namespace vf

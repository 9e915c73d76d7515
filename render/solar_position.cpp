// The NOAA solar calculator's steps (solar_position.h), each with Meeus's equation number.
#include "render/solar_position.h"

#include <cmath>
#include <numbers>

namespace vf {
namespace {

constexpr double kRad = std::numbers::pi / 180;

double sinD(double d) { return std::sin(d * kRad); }
double cosD(double d) { return std::cos(d * kRad); }
double tanD(double d) { return std::tan(d * kRad); }

// NOAA's refraction in degrees at true elevation e (degrees): Saemundsson-like fits by range,
// for the standard atmosphere.
double refraction(double e) {
  double arcsec = 0;
  if (e > 85) {
    arcsec = 0;
  } else if (e > 5) {
    const double t = tanD(e);
    arcsec = 58.1 / t - 0.07 / (t * t * t) + 0.000086 / std::pow(t, 5);
  } else if (e > -0.575) {
    arcsec = 1735 + e * (-518.2 + e * (103.4 + e * (-12.79 + e * 0.711)));
  } else {
    arcsec = -20.774 / tanD(e);
  }
  return arcsec / 3600;
}

}  // namespace

double julianDay(int year, int month, int day, double utcSeconds) {
  // Meeus eq. 7.1 for the Gregorian calendar.
  if (month <= 2) {
    year -= 1;
    month += 12;
  }
  const double a = std::floor(year / 100.0);
  const double b = 2 - a + std::floor(a / 4);
  return std::floor(365.25 * (year + 4716)) + std::floor(30.6001 * (month + 1)) + day + b - 1524.5 +
         utcSeconds / 86400;
}

SolarCoordinates solarCoordinates(double jd) {
  const double t = (jd - 2451545.0) / 36525;  // Julian centuries from J2000.0, eq. 25.1
  const double l0 = std::fmod(280.46646 + t * (36000.76983 + t * 0.0003032), 360);  // eq. 25.2
  const double m = 357.52911 + t * (35999.05029 - 0.0001537 * t);                   // eq. 25.3
  const double e = 0.016708634 - t * (0.000042037 + 0.0000001267 * t);              // eq. 25.4
  const double c = sinD(m) * (1.914602 - t * (0.004817 + 0.000014 * t)) +
                   sinD(2 * m) * (0.019993 - 0.000101 * t) + sinD(3 * m) * 0.000289;
  const double omega = 125.04 - 1934.136 * t;
  const double lambda = l0 + c - 0.00569 - 0.00478 * sinD(omega);  // apparent longitude
  const double eps0 = 23 + (26 + (21.448 - t * (46.815 + t * (0.00059 - t * 0.001813))) / 60) / 60;
  const double eps = eps0 + 0.00256 * cosD(omega);  // eq. 25.8 (obliquity, corrected)
  SolarCoordinates s;
  s.apparentLongitudeDegrees = std::fmod(lambda + 360, 360);
  s.declinationDegrees = std::asin(sinD(eps) * sinD(lambda)) / kRad;  // eq. 25.7
  // Smart's formula, eq. 28.3, in minutes of time (4 per degree).
  const double y = tanD(eps / 2) * tanD(eps / 2);
  const double eq = y * sinD(2 * l0) - 2 * e * sinD(m) + 4 * e * y * sinD(m) * cosD(2 * l0) -
                    0.5 * y * y * sinD(4 * l0) - 1.25 * e * e * sinD(2 * m);
  s.equationOfTimeMinutes = 4 * eq / kRad;
  return s;
}

SunPosition sunPosition(int year, int month, int day, double utcSeconds, double latitude,
                        double longitude) {
  const SolarCoordinates s = solarCoordinates(julianDay(year, month, day, utcSeconds));
  // True solar time and the hour angle, degrees west of the meridian.
  const double trueSolarMinutes =
      std::fmod(utcSeconds / 60 + s.equationOfTimeMinutes + 4 * longitude + 2880, 1440);
  const double hour = trueSolarMinutes / 4 - 180;
  const double d = s.declinationDegrees;
  // Meeus eq. 13.5 and 13.6: azimuth from the south, westwards; +180 turns it to from north.
  const double azimuth =
      std::atan2(sinD(hour), cosD(hour) * sinD(latitude) - tanD(d) * cosD(latitude)) / kRad + 180;
  const double elevation =
      std::asin(sinD(latitude) * sinD(d) + cosD(latitude) * cosD(d) * cosD(hour)) / kRad;
  return SunPosition{std::fmod(azimuth + 360, 360), elevation + refraction(elevation)};
}

}  // namespace vf

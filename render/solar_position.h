// Where the sun stands for a date, a UTC time and a place on the Earth: the NOAA Global
// Monitoring Laboratory's solar calculator algorithm, which takes its formulas from J. Meeus,
// "Astronomical Algorithms", 2nd ed. (1998): the sun's low-accuracy coordinates (ch. 25), the
// equation of time by Smart's formula (ch. 28, eq. 28.3), the horizontal coordinates (ch. 13)
// and NOAA's approximation of atmospheric refraction. Its stated accuracy is about 0.01 degree
// for the years 1800 to 2100; the scene loader accepts 1800 to 2200. Universal time is used for
// dynamical time (their difference, about a minute, moves the sun by less than 0.001 degree).
#pragma once

namespace vf {

// The sun's geocentric coordinates at Julian day `jd` (Meeus ch. 25, low accuracy).
struct SolarCoordinates {
  double apparentLongitudeDegrees = 0;  // lambda, ecliptic, corrected for nutation and aberration
  double declinationDegrees = 0;        // delta
  double equationOfTimeMinutes = 0;     // apparent minus mean solar time
};
SolarCoordinates solarCoordinates(double julianDay);

// Julian day of a proleptic Gregorian date at `utcSeconds` after midnight (Meeus ch. 7).
double julianDay(int year, int month, int day, double utcSeconds);

// The sun as seen from latitude, longitude (degrees, north and east positive) at a date and UTC
// time: azimuth clockwise from true north and elevation above the horizon including refraction,
// degrees (negative below the horizon).
struct SunPosition {
  double azimuthDegrees = 0;
  double elevationDegrees = 0;
};
SunPosition sunPosition(int year, int month, int day, double utcSeconds, double latitudeDegrees,
                        double longitudeDegrees);

}  // namespace vf

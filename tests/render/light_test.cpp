// The light: the compass convention of [light], the default sun, the solar-position algorithm
// against the worked examples it comes from, and a DEM's place on the Earth. Oracles: Meeus,
// "Astronomical Algorithms" (2nd ed., 1998), examples 7.a, 25.a and 28.b; the worked example of
// Reda & Andreas (2004), "Solar position algorithm for solar radiation applications", Solar
// Energy 76, 577-589 (table A4.1), computed by a different, more precise algorithm; and the
// meridian convergence of a transverse Mercator grid from map-projection theory (Snyder,
// "Map Projections: A Working Manual", USGS PP 1395, eq. 8-13).
#include "render/light.h"

#include <cpl_conv.h>
#include <gtest/gtest.h>
#include <ogr_srs_api.h>

#include <cmath>
#include <numbers>

#include "render/solar_position.h"
#include "sim/core/error.h"
#include "sim/shape/geo_location.h"

namespace vf {
namespace {

constexpr double kDeg = std::numbers::pi / 180;

TEST(Light, CompassAzimuthIsClockwiseFromNorthAndElevationAboveTheHorizon) {
  EXPECT_LT((sunFromCompass(0, 0) - Vec3(0, 1, 0)).norm(), 1e-15);   // north: +y
  EXPECT_LT((sunFromCompass(90, 0) - Vec3(1, 0, 0)).norm(), 1e-15);  // east: +x
  EXPECT_LT((sunFromCompass(180, 0) - Vec3(0, -1, 0)).norm(), 1e-15);
  EXPECT_LT((sunFromCompass(270, 30) - Vec3(-std::cos(30 * kDeg), 0, 0.5)).norm(), 1e-15);
  EXPECT_LT((sunFromCompass(123, 90) - Vec3(0, 0, 1)).norm(), 1e-15);
}

TEST(Light, DefaultSunLightsBothFacesTheAutomaticCameraSeesUnequally) {
  // For any view, a box turned square to it shows two side faces; both must face the sun (and
  // not equally, or the edge between them vanishes), and shadows must fall away from the
  // camera.
  for (const double azimuth : {0.0, 33.7, 146.3, 250.0}) {
    const Vec3 view(std::sin(azimuth * kDeg), std::cos(azimuth * kDeg), 0);
    const Vec3 sun = defaultSunDirection(view);
    EXPECT_NEAR(sun.norm(), 1, 1e-15);
    EXPECT_NEAR(std::asin(sun.z()), 45 * kDeg, 1e-12);
    const Vec3 right = view.cross(Vec3::UnitZ());
    // The faces at 45 degrees either side of the way back to the camera.
    const Vec3 leftFace = (-view - right).normalized(), rightFace = (-view + right).normalized();
    EXPECT_GT(leftFace.dot(sun), 0.1) << azimuth;
    EXPECT_GT(rightFace.dot(sun), leftFace.dot(sun) + 0.1) << "lit from the right, " << azimuth;
    // The shadow falls along -sun's horizontal part: away from the camera.
    EXPECT_GT(Vec3(-sun.x(), -sun.y(), 0).dot(view), 0) << azimuth;
  }
}

TEST(SolarPosition, JulianDayOfMeeusExample7a) {
  // 1957 October 4.81 (Sputnik 1): JD 2436116.31.
  EXPECT_NEAR(julianDay(1957, 10, 4, 0.81 * 86400), 2436116.31, 1e-6);
  EXPECT_EQ(julianDay(2000, 1, 1, 12 * 3600), 2451545.0);  // J2000.0
}

TEST(SolarPosition, SunCoordinatesOfMeeusExamples25aAnd28b) {
  // 1992 October 13.0 TD. Meeus prints the low-accuracy method's apparent longitude as
  // 199.90895 and the declination as -7.78507 degrees (5 decimals: tolerance half a unit of
  // the last, plus his rounding of Omega to 264.65), and by Smart's formula (ex. 28.b) the
  // equation of time as 13 m 42.7 s (a tenth of a second).
  const SolarCoordinates s = solarCoordinates(2448908.5);
  EXPECT_NEAR(s.apparentLongitudeDegrees, 199.90895, 2e-5);
  EXPECT_NEAR(s.declinationDegrees, -7.78507, 1e-5);
  EXPECT_NEAR(s.equationOfTimeMinutes, 13 + 42.7 / 60, 0.1 / 60);
}

TEST(SolarPosition, AgreesWithTheSolarPositionAlgorithmsWorkedExample) {
  // Reda & Andreas: 2003 October 17, 12:30:30 local time at UTC-7, latitude 39.742476,
  // longitude -105.1786: topocentric zenith 50.11162 and azimuth 194.34024 degrees (SPA,
  // accurate to 0.0003). This algorithm differs by its low-accuracy sun (0.01 degree), by
  // neglecting parallax (0.0024 degree at most) and by refracting through the standard
  // atmosphere where the example has 820 mbar and 11 C (0.004 degree at this height): 0.03.
  const SunPosition p = sunPosition(2003, 10, 17, (19 * 60 + 30) * 60 + 30, 39.742476, -105.1786);
  EXPECT_NEAR(90 - p.elevationDegrees, 50.11162, 0.03);
  EXPECT_NEAR(p.azimuthDegrees, 194.34024, 0.03);
}

TEST(SolarPosition, NoonSunStandsOnTheMeridianAtTheHeightOfTheDeclination) {
  // At true solar noon the sun is due south (north of the tropics) at 90 - latitude + delta.
  const double jd = julianDay(2024, 6, 21, 12 * 3600);
  const SolarCoordinates s = solarCoordinates(jd);
  const double latitude = 47.3, longitude = 11.4;
  // Local true noon in UTC: 12:00 - longitude / 15 h - the equation of time.
  const double noon = (12 * 60 - 4 * longitude - s.equationOfTimeMinutes) * 60;
  const SunPosition p = sunPosition(2024, 6, 21, noon, latitude, longitude);
  EXPECT_NEAR(p.azimuthDegrees, 180, 0.02);
  // Refraction at 66 degrees is 0.007 degree; the declination moves 0.0001 in the 50 min
  // between the two instants.
  EXPECT_NEAR(p.elevationDegrees, 90 - latitude + s.declinationDegrees, 0.01);
}

// A terrain whose file coordinates are UTM zone 32 north (EPSG:32632, central meridian 9 E),
// moved by `shift` into the world.
Heightfield utmTerrain(const Vec3& shift) {
  Heightfield h;
  h.nx = h.ny = 3;
  h.cell = 10;
  h.z.assign(9, 0.0);
  OGRSpatialReferenceH srs = OSRNewSpatialReference(nullptr);
  EXPECT_EQ(OSRImportFromEPSG(srs, 32632), OGRERR_NONE);
  char* wkt = nullptr;
  OSRExportToWkt(srs, &wkt);
  h.crsWkt = wkt;
  CPLFree(wkt);
  OSRDestroySpatialReference(srs);
  shiftHeightfield(h, shift);
  return h;
}

// The UTM 32N coordinates of a WGS84 point (GDAL's forward projection; the test's input).
Vec3 toUtm(double latitude, double longitude) {
  OGRSpatialReferenceH wgs = OSRNewSpatialReference(nullptr), utm = OSRNewSpatialReference(nullptr);
  OSRSetWellKnownGeogCS(wgs, "WGS84");
  OSRImportFromEPSG(utm, 32632);
  OSRSetAxisMappingStrategy(wgs, OAMS_TRADITIONAL_GIS_ORDER);
  OSRSetAxisMappingStrategy(utm, OAMS_TRADITIONAL_GIS_ORDER);
  OGRCoordinateTransformationH t = OCTNewCoordinateTransformation(wgs, utm);
  double x = longitude, y = latitude, z = 0;
  OCTTransform(t, 1, &x, &y, &z);
  OCTDestroyCoordinateTransformation(t);
  OSRDestroySpatialReference(wgs);
  OSRDestroySpatialReference(utm);
  return Vec3(x, y, 0);
}

TEST(GeoLocation, CentralMeridianAndConvergenceOfAUtmGrid) {
  const Vec3 shift(-500000, -5260000, -100);  // a scene's [ground] offset
  const Heightfield h = utmTerrain(shift);
  // On the central meridian the grid's north is true north.
  const GeoLocation onMeridian = geoLocation(h, Vec3(500000, 5260000, 0) + shift, "here");
  EXPECT_NEAR(onMeridian.longitudeDegrees, 9, 1e-9);
  EXPECT_NEAR(onMeridian.trueNorthDegrees, 0, 1e-6);
  // Two degrees east of it at 47.5 N: the grid turns clockwise of the meridians by the
  // convergence gamma = dl sin(phi) (1 + dl^2 cos^2(phi) / 3), dl in radians (Snyder eq. 8-13,
  // the terms left out are below 1e-5 degree here), so true north lies gamma counter-clockwise
  // of the grid's north.
  const GeoLocation east = geoLocation(h, toUtm(47.5, 11) + shift, "here");
  EXPECT_NEAR(east.latitudeDegrees, 47.5, 1e-7);
  EXPECT_NEAR(east.longitudeDegrees, 11, 1e-7);
  const double dl = 2 * kDeg, phi = 47.5 * kDeg;
  const double gamma = dl * std::sin(phi) * (1 + dl * dl * std::cos(phi) * std::cos(phi) / 3);
  // The 0.001-degree step north sees the meridian straight to 1e-4 degree.
  EXPECT_NEAR(east.trueNorthDegrees, -gamma / kDeg, 2e-4);
}

TEST(GeoLocation, ADemWithoutAPlaceOnTheEarthIsAnErrorNamingTheLight) {
  Heightfield none = utmTerrain(Vec3::Zero());
  none.crsWkt.clear();
  try {
    geoLocation(none, Vec3::Zero(), "scene.toml:7:1");
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.where(), "scene.toml:7:1");
    EXPECT_NE(e.message().find("no coordinate reference system"), std::string::npos) << e.what();
  }
  // What GDAL reads from a grid without a .prj: a local engineering CRS.
  none.crsWkt = R"wkt(ENGCRS["unnamed",EDATUM[""],CS[Cartesian,2],AXIS["(E)",east,ORDER[1],
    LENGTHUNIT["unknown",1]],AXIS["(N)",north,ORDER[2],LENGTHUNIT["unknown",1]]])wkt";
  EXPECT_THROW(geoLocation(none, Vec3::Zero(), "here"), InputError);
}

TEST(Light, DateAndTimeGiveTheSunAtTheTerrainsCentreTurnedToTheGrid) {
  const Vec3 shift(-500000, -5260000, 0);
  Heightfield h = utmTerrain(Vec3::Zero());
  // Move the grid two degrees east of the central meridian, so the grid's north is not true
  // north there.
  const Vec3 at = toUtm(47.5, 11);
  h.x0 = at.x() - 10, h.y0 = at.y() - 10;  // centre sample on the point
  shiftHeightfield(h, shift);
  LightSpec spec;
  spec.date = CivilDate{2024, 6, 21};
  spec.utcSeconds = 9 * 3600;
  spec.where = "scene.toml:3:1";
  const SceneLight light = sceneLight(spec, &h);
  ASSERT_TRUE(light.sunDirection);
  const Vec3 s = *light.sunDirection;
  const SunPosition expected = sunPosition(2024, 6, 21, 9 * 3600, 47.5, 11);
  EXPECT_NEAR(std::asin(s.z()) / kDeg, expected.elevationDegrees, 1e-6);
  const double gridAzimuth = std::atan2(s.x(), s.y()) / kDeg;
  const GeoLocation g = geoLocation(h, Vec3(h.x0 + 10, h.y0 + 10, 0), "here");
  EXPECT_NEAR(gridAzimuth, expected.azimuthDegrees + g.trueNorthDegrees, 1e-6);
  EXPECT_LT(g.trueNorthDegrees, -1);  // the turn is there to be made
  // Colours: intensity x color.
  EXPECT_LT((light.colors.sun - Vec3(1.75, 1.75 * 0.96f, 1.75 * 0.886f)).norm(), 1e-12);

  // At night there is no sun to place; without a terrain there is no place.
  spec.utcSeconds = 0;
  EXPECT_THROW(sceneLight(spec, &h), InputError);
  spec.utcSeconds = 9 * 3600;
  try {
    sceneLight(spec, nullptr);
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.where(), "scene.toml:3:1");
  }
}

}  // namespace
}  // namespace vf

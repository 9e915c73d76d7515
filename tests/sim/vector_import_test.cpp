// Vector files in the DEM's CRS: shapes written by hand (GeoJSON text) or through OGR
// (GeoPackage) come back with the coordinates they were written with, transformed where the
// file's CRS differs by what the projection's definition fixes, and every bad file is one error
// naming it.
#include "sim/shape/vector_import.h"

#include <gdal.h>
#include <gtest/gtest.h>
#include <ogr_api.h>
#include <ogr_srs_api.h>

#include <filesystem>
#include <fstream>
#include <functional>
#include <string>

#include "sim/core/error.h"
#include "sim/shape/crs.h"

namespace vf {
namespace {

namespace fs = std::filesystem;

fs::path scratch() {
  const fs::path dir = fs::temp_directory_path() / "voxfall_vector_import_test";
  fs::create_directories(dir);
  return dir;
}

std::string writeText(const std::string& name, const std::string& text) {
  const fs::path p = scratch() / name;
  std::ofstream(p) << text;
  return p.string();
}

std::string geoJson(const std::string& crs, const std::string& features) {
  std::string s = R"({"type": "FeatureCollection",)";
  if (!crs.empty()) s += R"("crs": {"type": "name", "properties": {"name": ")" + crs + R"("}},)";
  return s + R"("features": [)" + features + "]}";
}

const std::string kLambert = "urn:ogc:def:crs:EPSG::31287";  // MGI / Austria Lambert

std::string austria() { return parseCrs("EPSG:31287").wkt; }

void expectPoint(const std::array<double, 2>& p, double x, double y, double tol) {
  EXPECT_NEAR(p[0], x, tol);
  EXPECT_NEAR(p[1], y, tol);
}

TEST(VectorImport, ShapesInTheDemsCrsKeepTheirCoordinatesAndAttributes) {
  const std::string path = writeText(
      "same.geojson",
      geoJson(kLambert,
              R"({"type": "Feature", "properties": {"weight": 2.5, "name": "north", "n": 3},
                  "geometry": {"type": "Polygon", "coordinates": [
                    [[100, 200], [140, 200], [140, 260], [100, 260], [100, 200]],
                    [[110, 210], [120, 210], [120, 220], [110, 200]]]}},
                 {"type": "Feature", "properties": {},
                  "geometry": {"type": "LineString", "coordinates": [[0, 0], [5, 1], [9, 4]]}},
                 {"type": "Feature", "properties": {"dbh": 32},
                  "geometry": {"type": "MultiPoint", "coordinates": [[7, 8], [9, 10]]}})"));
  const auto f = readVectorFile(path, austria());
  ASSERT_EQ(f.size(), 4u);  // the multipoint becomes two features
  EXPECT_EQ(f[0].kind, VectorFeature::Kind::kPolygon);
  ASSERT_EQ(f[0].rings.size(), 2u);
  ASSERT_EQ(f[0].rings[0].size(), 4u);  // the closing vertex dropped
  expectPoint(f[0].rings[0][2], 140, 260, 0);
  EXPECT_EQ(f[0].rings[1].size(), 4u);  // a hole whose last vertex is not its first keeps it
  EXPECT_EQ(f[0].number("weight"), 2.5);
  EXPECT_EQ(f[0].number("n"), 3.0);
  EXPECT_FALSE(f[0].number("name").has_value());  // text is not a number
  EXPECT_EQ(f[1].kind, VectorFeature::Kind::kLine);
  ASSERT_EQ(f[1].rings[0].size(), 3u);
  expectPoint(f[1].rings[0][1], 5, 1, 0);
  EXPECT_FALSE(f[1].number("weight").has_value());
  EXPECT_EQ(f[2].kind, VectorFeature::Kind::kPoint);
  expectPoint(f[3].rings[0][0], 9, 10, 0);
  EXPECT_EQ(f[3].number("dbh"), 32.0);
  EXPECT_EQ(f[2].id, f[3].id);
}

// Austria Lambert's definition puts its origin (47.5 N, 13 deg 20' E on MGI) at the false
// easting and northing (400 km, 400 km); a point given in MGI's geographic coordinates (the
// same datum, so no datum shift enters) must land there.
TEST(VectorImport, AnotherCrsOfTheSameDatumIsProjectedOntoTheDem) {
  const std::string path = writeText(
      "mgi.geojson", geoJson("urn:ogc:def:crs:EPSG::4312",
                             R"({"type": "Feature", "properties": {}, "geometry": {"type": "Point",
                  "coordinates": [13.333333333333333, 47.5]}})"));
  const auto f = readVectorFile(path, austria());
  ASSERT_EQ(f.size(), 1u);
  expectPoint(f[0].rings[0][0], 400000, 400000, 1e-3);
}

// A GeoPackage written through OGR, in the DEM's CRS, with its layer chosen by name.
std::string writeGeoPackage(const std::string& name, bool withCrs) {
  GDALAllRegister();
  const fs::path p = scratch() / name;
  fs::remove(p);
  GDALDriverH drv = GDALGetDriverByName("GPKG");
  GDALDatasetH ds = GDALCreate(drv, p.c_str(), 0, 0, 0, GDT_Unknown, nullptr);
  OGRSpatialReferenceH srs = nullptr;
  if (withCrs) {
    srs = OSRNewSpatialReference(nullptr);
    OSRImportFromEPSG(srs, 31287);
  }
  OGRLayerH layer = GDALDatasetCreateLayer(ds, "sources", srs, wkbPolygon, nullptr);
  OGRFieldDefnH field = OGR_Fld_Create("weight", OFTReal);
  OGR_L_CreateField(layer, field, 1);
  OGR_Fld_Destroy(field);
  OGRFeatureH f = OGR_F_Create(OGR_L_GetLayerDefn(layer));
  OGR_F_SetFieldDouble(f, 0, 0.75);
  OGRGeometryH g = nullptr;
  char wkt[] = "POLYGON ((1000 2000, 1100 2000, 1100 2050, 1000 2000))";
  char* cursor = wkt;
  OGR_G_CreateFromWkt(&cursor, nullptr, &g);
  OGR_F_SetGeometryDirectly(f, g);
  EXPECT_EQ(OGR_L_CreateFeature(layer, f), OGRERR_NONE);
  OGR_F_Destroy(f);
  if (srs) OSRDestroySpatialReference(srs);
  GDALClose(ds);
  return p.string();
}

TEST(VectorImport, AGeoPackageLayerIsReadByName) {
  const std::string path = writeGeoPackage("sources.gpkg", true);
  const auto f = readVectorFile(path, austria(), "sources");
  ASSERT_EQ(f.size(), 1u);
  ASSERT_EQ(f[0].rings[0].size(), 3u);
  expectPoint(f[0].rings[0][1], 1100, 2000, 0);
  EXPECT_EQ(f[0].number("weight"), 0.75);
}

void expectInputError(const std::function<void()>& read, const std::string& path,
                      const std::string& words) {
  try {
    read();
    ADD_FAILURE() << "no error for " << path;
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find(path), std::string::npos) << what;
    EXPECT_NE(what.find(words), std::string::npos) << what;
  }
}

TEST(VectorImport, BadFilesAreOneErrorNamingTheFile) {
  const std::string missing = (scratch() / "nowhere.gpkg").string();
  expectInputError([&] { readVectorFile(missing, austria()); }, missing, "not found");

  const std::string noCrs = writeGeoPackage("no_crs.gpkg", false);
  expectInputError([&] { readVectorFile(noCrs, austria()); }, noCrs,
                   "names no coordinate reference system");

  const std::string good = writeGeoPackage("good.gpkg", true);
  expectInputError([&] { readVectorFile(good, ""); }, good, "[ground] crs");
  expectInputError([&] { readVectorFile(good, austria(), "roads"); }, good, "no layer named");

  const std::string text = writeText("garbage.gpkg", "not a vector file\n");
  expectInputError([&] { readVectorFile(text, austria()); }, text, "cannot read");

  const std::string empty =
      writeText("empty.geojson", geoJson(kLambert, R"({"type": "Feature", "properties": {},
        "geometry": {"type": "LineString", "coordinates": []}})"));
  expectInputError([&] { readVectorFile(empty, austria()); }, empty, "empty geometry");
}

}  // namespace
}  // namespace vf

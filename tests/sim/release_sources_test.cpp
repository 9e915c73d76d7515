// Release sources from GIS: polygons of a GeoPackage (written through OGR in the chute DEM's
// projected CRS) and several weighted sources, drawn where and as often as they say. Counts are
// checked against the binomial distribution the weights imply: with N draws of probability p,
// the count lies within 4 standard deviations, sqrt(N p (1 - p)), of N p but for a chance
// below 1e-4 (and the seeds are fixed, so a pass is repeatable).
#include "sim/ensemble/release_sources.h"

#include <gdal.h>
#include <gtest/gtest.h>
#include <ogr_api.h>
#include <ogr_srs_api.h>

#include <cmath>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "sim/core/error.h"
#include "sim/core/prng.h"
#include "sim/ensemble/ensemble.h"
#include "sim/scene/scene.h"
#include "tests/support/chute_dem.h"

namespace vf {
namespace {

namespace fs = std::filesystem;

constexpr int kDraws = 400;

void expectBinomial(int count, double p, const std::string& what) {
  const double sigma = std::sqrt(kDraws * p * (1 - p));
  EXPECT_NEAR(count, kDraws * p, 4 * sigma) << what;
}

// A polygon layer "zones" in EPSG:31287 with a numeric field "share"; each polygon is WKT in
// the DEM's file coordinates.
void writeZones(const fs::path& path, const std::vector<std::pair<std::string, double>>& zones) {
  GDALAllRegister();
  fs::remove(path);
  GDALDatasetH ds =
      GDALCreate(GDALGetDriverByName("GPKG"), path.c_str(), 0, 0, 0, GDT_Unknown, nullptr);
  ASSERT_NE(ds, nullptr);
  OGRSpatialReferenceH srs = OSRNewSpatialReference(nullptr);
  OSRImportFromEPSG(srs, 31287);
  OGRLayerH layer = GDALDatasetCreateLayer(ds, "zones", srs, wkbUnknown, nullptr);
  OGRFieldDefnH field = OGR_Fld_Create("share", OFTReal);
  OGR_L_CreateField(layer, field, 1);
  OGR_Fld_Destroy(field);
  for (const auto& [wkt, share] : zones) {
    OGRFeatureH f = OGR_F_Create(OGR_L_GetLayerDefn(layer));
    OGR_F_SetFieldDouble(f, 0, share);
    std::string text = wkt;
    char* cursor = text.data();
    OGRGeometryH g = nullptr;
    OGR_G_CreateFromWkt(&cursor, nullptr, &g);
    OGR_F_SetGeometryDirectly(f, g);
    EXPECT_EQ(OGR_L_CreateFeature(layer, f), OGRERR_NONE);
    OGR_F_Destroy(f);
  }
  OSRDestroySpatialReference(srs);
  GDALClose(ds);
}

class ReleaseSourcesTest : public test::ChuteFolderTest {
 protected:
  ReleaseSources sources(const std::string& release) {
    test::writeChuteScene(dir_, "shape = \"rock\"\n" + release);
    spec_ = loadScene((dir_ / "scene.toml").string());
    dem_ = std::make_shared<const Heightfield>(*sceneWorldDef(spec_).terrain);
    return ReleaseSources(spec_.ensemble->releases, dem_, spec_.terrainPath);
  }
  SceneSpec spec_;
  std::shared_ptr<const Heightfield> dem_;
};

// Two squares west and east on the chute (DEM x 1004..1014 and 1030..1040, y 5004..5014), the
// west one with an 8 m x 8 m hole; the scene's offset (-1000, -5000) puts them at world
// x 4..14 and 30..40.
const char* kWest =
    "POLYGON ((1004 5004, 1014 5004, 1014 5014, 1004 5014, 1004 5004),"
    " (1005 5005, 1013 5005, 1013 5013, 1005 5013, 1005 5005))";
const char* kEast = "POLYGON ((1030 5004, 1040 5004, 1040 5014, 1030 5014, 1030 5004))";

bool inWest(const Point2& p) { return p[0] >= 4 && p[0] <= 14 && p[1] >= 4 && p[1] <= 14; }
bool inHole(const Point2& p) { return p[0] > 5 && p[0] < 13 && p[1] > 5 && p[1] < 13; }
bool inEast(const Point2& p) { return p[0] >= 30 && p[0] <= 40 && p[1] >= 4 && p[1] <= 14; }

TEST_F(ReleaseSourcesTest, FeaturesOfAGeoPackageReleaseByTheirWeightField) {
  writeZones(dir_ / "zones.gpkg", {{kWest, 1}, {kEast, 3}});
  const ReleaseSources s =
      sources("release = { file = \"zones.gpkg\", weight_field = \"share\" }\n");
  int east = 0;
  for (int i = 0; i < kDraws; ++i) {
    const Point2 p = s.draw(realisationSeed(5, i));
    ASSERT_TRUE(inEast(p) || (inWest(p) && !inHole(p))) << p[0] << ", " << p[1];
    east += inEast(p);
  }
  expectBinomial(east, 0.75, "east share 3 of 4");
}

TEST_F(ReleaseSourcesTest, WithoutAWeightFieldFeaturesReleaseByTheirArea) {
  // West: 100 - 64 = 36 m^2 (the hole excluded), east: 100 m^2.
  writeZones(dir_ / "zones.gpkg", {{kWest, 1}, {kEast, 1}});
  const ReleaseSources s = sources("release = { file = \"zones.gpkg\", layer = \"zones\" }\n");
  int east = 0;
  for (int i = 0; i < kDraws; ++i) east += inEast(s.draw(realisationSeed(6, i)));
  expectBinomial(east, 100.0 / 136.0, "east by area");
}

TEST_F(ReleaseSourcesTest, SeveralSourcesReleaseByTheirWeights) {
  const ReleaseSources s = sources(
      "[[ensemble.release]]\npoints = [[1020.0, 5010.0]]\nweight = 1\n"
      "[[ensemble.release]]\narea = [[1030, 5004], [1040, 5004], [1040, 5014], [1030, 5014]]\n"
      "weight = 4\n");
  int point = 0;
  for (int i = 0; i < kDraws; ++i) {
    const Point2 p = s.draw(realisationSeed(7, i));
    const bool atPoint = p[0] == 20 && p[1] == 10;
    ASSERT_TRUE(atPoint || inEast(p)) << p[0] << ", " << p[1];
    point += atPoint;
  }
  expectBinomial(point, 0.2, "the point source, weight 1 of 5");
  EXPECT_EQ(s.outlines().size(), 2u);
}

TEST_F(ReleaseSourcesTest, OneSourceDrawsNoChoiceNumbers) {
  // With one source of one part the generator goes straight to the point: a points release
  // of n points takes entry floor(u n) of the first uniform u, as before several sources.
  const ReleaseSources s = sources("release = { points = [[1005, 5007], [1009, 5015]] }\n");
  for (int i = 0; i < 20; ++i) {
    Prng rng(realisationSeed(8, i));
    const bool second = rng.uniform() * 2 >= 1;
    const Point2 p = s.draw(realisationSeed(8, i));
    EXPECT_EQ(p[0], second ? 9.0 : 5.0);
  }
}

void expectLoadError(const std::function<void()>& load, const std::string& words) {
  try {
    load();
    ADD_FAILURE() << "no error; expected: " << words;
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
  }
}

TEST_F(ReleaseSourcesTest, BadSourcesAreOneErrorNamingTheFileOrKey) {
  expectLoadError([&] { sources("release = { file = \"none.gpkg\" }\n"); },
                  "release vector file not found");
  writeZones(dir_ / "far.gpkg", {{"POLYGON ((900 5004, 910 5004, 910 5014, 900 5004))", 1}});
  expectLoadError([&] { sources("release = { file = \"far.gpkg\" }\n"); },
                  "far.gpkg: release.file feature 1 vertex (900.000, 5004.000) lies outside");
  writeZones(dir_ / "mixed.gpkg", {{kEast, 1}, {"POINT (1020 5010)", 1}});
  expectLoadError([&] { sources("release = { file = \"mixed.gpkg\" }\n"); },
                  "mixes points, lines and areas; give 'weight_field'");
  writeZones(dir_ / "zero.gpkg", {{kEast, 0}});
  expectLoadError(
      [&] { sources("release = { file = \"zero.gpkg\", weight_field = \"share\" }\n"); },
      "every feature needs a weight > 0");
  expectLoadError([&] { sources("release = { points = [[1005, 5007]], layer = \"x\" }\n"); },
                  "'release.layer' belongs to a 'file' source");
  expectLoadError([&] { sources("[[ensemble.release]]\npoints = [[1005, 5007]]\nweight = -1\n"); },
                  "'release[0].weight' must be > 0");
}

}  // namespace
}  // namespace vf

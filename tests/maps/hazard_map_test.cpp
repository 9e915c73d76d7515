// Hazard maps (render/maps): each part against an oracle that does not come from the code.
//   - hillshade: on planes, Horn's differences are exact, so every interior sample equals the
//     analytic cos(zenith) cos(slope) + sin(zenith) sin(slope) cos(azimuth - aspect) with the
//     plane's own slope and aspect (written down by hand below), to rounding;
//   - viridis: lightness (CIE L*, computed here from sRGB) rises along its 256 entries, and the
//   ends and middle are matplotlib's published #440154, #21918c, #fde725;
//   - the map PNG, read back: the highest and lowest values show the colour map's ends at the
//     pixels the layout puts them, a cell without a value shows the plane's analytic hillshade
//     as grey, the release outline, line and marker are red where they lie and nowhere else;
//     a map smaller than its grid still shows a one-sample-wide track;
//     the same input gives the same bytes;
//   - errors: a wrong number of values, an unwritable place, an empty runout list: InputError
//     and no file;
//   - the Tyrol DEM (GeoTIFF with a CRS): axes in its file coordinates, as gdalinfo gives them.
#include "render/maps/hazard_map.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <numbers>

#include "render/maps/colour_map.h"
#include "render/maps/hillshade.h"
#include "render/output/png_writer.h"
#include "sim/core/error.h"
#include "tests/render/render_test_util.h"

namespace vf {
namespace {

namespace fs = std::filesystem;
constexpr double kDeg = std::numbers::pi / 180;

// A plane z = z0 + a x + b y sampled on an nx x ny grid.
Heightfield plane(int nx, int ny, double cell, double a, double b, double x0 = 0, double y0 = 0) {
  Heightfield h;
  h.nx = nx, h.ny = ny, h.cell = cell, h.x0 = x0, h.y0 = y0;
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) h.z.push_back(100 + a * (x0 + i * cell) + b * (y0 + j * cell));
  h.zMin = *std::min_element(h.z.begin(), h.z.end());
  h.zMax = *std::max_element(h.z.begin(), h.z.end());
  return h;
}

// The hillshade of a surface of slope and aspect (deg) under the default sun (315, 45).
double analyticShade(double slopeDeg, double aspectDeg) {
  const double zenith = 45 * kDeg, azimuth = 315 * kDeg;
  return std::max(
      0.0, std::cos(zenith) * std::cos(slopeDeg * kDeg) +
               std::sin(zenith) * std::sin(slopeDeg * kDeg) * std::cos(azimuth - aspectDeg * kDeg));
}

// Every interior sample of `h` against the analytic value; the tolerance is rounding only
// (Horn's differences of a plane are its exact gradient).
void expectInteriorShade(const Heightfield& h, double expected) {
  const std::vector<double> s = hillshade(h);
  ASSERT_EQ(s.size(), h.z.size());
  for (int j = 1; j + 1 < h.ny; ++j)
    for (int i = 1; i + 1 < h.nx; ++i)
      EXPECT_NEAR(s[static_cast<std::size_t>(j) * h.nx + i], expected, 1e-12) << i << "," << j;
}

TEST(Hillshade, PlaneFacingEastMatchesTheAnalyticValue) {
  // z falls 0.5 m per metre eastward: slope atan(0.5), facing east (aspect 90 deg), away from
  // a north-west sun.
  expectInteriorShade(plane(7, 6, 2.0, -0.5, 0), analyticShade(std::atan(0.5) / kDeg, 90));
}

TEST(Hillshade, PlaneFacingNorthWestByNorthMatchesTheAnalyticValue) {
  // Gradient (0.3, -0.4): downhill (-0.3, 0.4), i.e. north and a little west; aspect
  // atan2(-0.3, 0.4) = -36.87 deg; slope atan(0.5). A sign slip in either axis moves the aspect
  // to another quadrant and changes the value.
  expectInteriorShade(plane(6, 8, 3.0, 0.3, -0.4),
                      analyticShade(std::atan(0.5) / kDeg, std::atan2(-0.3, 0.4) / kDeg));
}

TEST(Hillshade, SlopeFacingTheSunSquarelyIsFullyLitAndFlatGroundIsCosZenith) {
  // Facing north-west (315 deg) at 45 deg of slope the surface faces the sun: 1 exactly.
  const double g = 1 / std::sqrt(2.0);
  expectInteriorShade(plane(5, 5, 1.0, g, -g), 1.0);
  expectInteriorShade(plane(5, 5, 1.0, 0, 0), std::cos(45 * kDeg));
}

TEST(Hillshade, NoDataStaysNoDataAndItsNeighboursAreStillShaded) {
  Heightfield h = plane(6, 6, 1.0, -0.5, 0);
  h.z[2 * 6 + 3] = std::nan("");
  const std::vector<double> s = hillshade(h);
  EXPECT_TRUE(std::isnan(s[2 * 6 + 3]));
  for (std::size_t k = 0; k < s.size(); ++k) {
    if (k == 2 * 6 + 3) continue;
    EXPECT_TRUE(s[k] >= 0 && s[k] <= 1) << k;
  }
}

// CIE L* of an 8-bit sRGB colour (IEC 61966-2-1 decoding, Y from the sRGB primaries, D65).
double lightness(const Rgb8& c) {
  const auto lin = [](std::uint8_t v) {
    const double u = v / 255.0;
    return u <= 0.04045 ? u / 12.92 : std::pow((u + 0.055) / 1.055, 2.4);
  };
  const double y = 0.2126 * lin(c.r) + 0.7152 * lin(c.g) + 0.0722 * lin(c.b);
  return y > 216.0 / 24389 ? 116 * std::cbrt(y) - 16 : 24389.0 / 27 * y;
}

TEST(ColourMap, ViridisLightnessRises) {
  // In the float definition L* rises by 0.28 to 0.35 per entry; rounding to 8 bits moves an
  // entry's L* by up to 0.18, so two neighbours may tie or swap by a few hundredths, but
  // entries two apart (>= 0.56 apart before rounding) must stay in order, and the whole map
  // spans L* from about 16 to 92.
  const auto& t = viridisTable();
  for (int k = 2; k < 256; ++k) EXPECT_GT(lightness(t[k]), lightness(t[k - 2])) << k;
  EXPECT_LT(lightness(t[0]), 20);
  EXPECT_GT(lightness(t[255]), 90);
}

TEST(ColourMap, ViridisEndsAndMiddleAreThePublishedColours) {
  // matplotlib's documentation and colormap reference give viridis as #440154 .. #21918c
  // (its entry 128, the middle) .. #fde725.
  EXPECT_EQ(viridis(0.0), (Rgb8{0x44, 0x01, 0x54}));
  EXPECT_EQ(viridis(0.5), (Rgb8{0x21, 0x91, 0x8c}));
  EXPECT_EQ(viridis(1.0), (Rgb8{0xfd, 0xe7, 0x25}));
  EXPECT_EQ(viridis(-3.0), viridis(0.0));
  EXPECT_EQ(viridis(7.0), viridis(1.0));
  EXPECT_EQ(viridis(std::nan("")), viridis(0.0));
}

// The test map: 20 x 16 samples, 5 m apart, a plane falling 0.5 m/m eastward; every value NaN
// except a high and a low cell.
struct TestMap {
  Heightfield dem = plane(20, 16, 5.0, -0.5, 0, 100, 200);
  MapLayer layer{"energy_p95", "Kinetic energy, 95th percentile", "kJ", {}};
  std::vector<std::vector<Vec2>> release;
  static constexpr int kHiI = 14, kHiJ = 9, kLoI = 9, kLoJ = 12, kNanI = 10, kNanJ = 5;
  TestMap() {
    layer.values.assign(dem.z.size(), std::nan(""));
    layer.values[kHiJ * 20 + kHiI] = 250;
    layer.values[kLoJ * 20 + kLoI] = 4;
    layer.values[kLoJ * 20 + kLoI + 1] = 100;
    // A square over samples 2..5 x 2..4 (world corners on sample centres), a line, a point.
    const auto at = [this](double i, double j) {
      return Vec2(dem.x0 + i * dem.cell, dem.y0 + j * dem.cell);
    };
    release = {{at(2, 2), at(5, 2), at(5, 4), at(2, 4)}, {at(8, 1), at(12, 1)}, {at(16, 6)}};
  }
};

const Rgb8 kRed{0xe4, 0x1a, 0x1c};

Rgb8 pixelAt(const Image& im, double column, double row) {
  const std::uint8_t* p = im.pixel(static_cast<int>(column), static_cast<int>(row));
  return Rgb8{p[0], p[1], p[2]};
}

// Whether any pixel within `r` px of (column, row) has colour `c`.
bool colourNear(const Image& im, double column, double row, int r, const Rgb8& c) {
  for (int y = int(row) - r; y <= int(row) + r; ++y)
    for (int x = int(column) - r; x <= int(column) + r; ++x)
      if (x >= 0 && y >= 0 && x < im.width && y < im.height && pixelAt(im, x, y) == c) return true;
  return false;
}

TEST(HazardMap, UnpassedCellsAndCellsWithoutDepositsHaveNoValueOnTheMap) {
  const std::vector<double> passages{0, 3, 1, 2};
  const std::vector<double> deposited{0, 2, 0, 1};
  const std::vector<double> energy{NAN, 40.0, 5.0, 0.0};
  const std::vector<double> d = vf::mappedValues("deposited", deposited, passages);
  EXPECT_TRUE(std::isnan(d[0]));  // not passed
  EXPECT_EQ(d[1], 2.0);
  EXPECT_TRUE(std::isnan(d[2]));  // passed, nothing stopped there
  EXPECT_EQ(d[3], 1.0);
  const std::vector<double> p = vf::mappedValues("passages", passages, passages);
  EXPECT_TRUE(std::isnan(p[0]));
  EXPECT_EQ(p[2], 1.0);
  // Other statistics keep a 0 where a rock passed: an energy of 0 is a value.
  const std::vector<double> e = vf::mappedValues("energy_mean", energy, passages);
  EXPECT_TRUE(std::isnan(e[0]));
  EXPECT_EQ(e[3], 0.0);
}

TEST(HazardMap, ValuesHillshadeAndReleaseAreasLandWhereTheLayoutSays) {
  test::ScratchDir dir("hazard_map");
  const TestMap m;
  const std::string path = (dir.path() / "energy_p95.png").string();
  writeHazardMap(m.dem, m.layer, m.release, path);
  const Image im = readPng(path);
  const MapFrame f = hazardMapFrame(m.dem);
  ASSERT_EQ(im.width, f.width);
  ASSERT_EQ(im.height, f.height);
  EXPECT_EQ(f.plotWidth, kMapLongSidePx);  // 20 x 16 samples: 800 x 640 px, 40 px a sample
  EXPECT_EQ(f.plotHeight, 640);
  const auto centre = [&](int i, int j) {
    return std::pair{f.columnOf(m.dem.x0 + i * m.dem.cell), f.rowOf(m.dem.y0 + j * m.dem.cell)};
  };
  // The highest value is the top of the colour map, the lowest the bottom.
  const auto [hx, hy] = centre(TestMap::kHiI, TestMap::kHiJ);
  EXPECT_EQ(pixelAt(im, hx, hy), viridis(1.0));
  const auto [lx, ly] = centre(TestMap::kLoI, TestMap::kLoJ);
  EXPECT_EQ(pixelAt(im, lx, ly), viridis(0.0));
  // No value: the hillshade of the plane (slope atan 0.5, facing east), grey.
  const auto [nx, ny] = centre(TestMap::kNanI, TestMap::kNanJ);
  const double shade = analyticShade(std::atan(0.5) / kDeg, 90);
  const auto grey = static_cast<std::uint8_t>(
      std::lround(255 * (kHillshadeFloor + (1 - kHillshadeFloor) * shade)));
  EXPECT_EQ(pixelAt(im, nx, ny), (Rgb8{grey, grey, grey}));
  // The outline's top edge, the line's middle and the marker are red (3 px lines: the middle
  // pixel row is fully covered whatever the anti-aliasing); far from them, no red.
  for (const auto& [ei, ej] : {std::pair{3.5, 2.0}, {5.0, 3.0}, {3.5, 4.0}, {2.0, 3.0}}) {
    // The midpoint of each side of the outline, the closing side (2, 4) -> (2, 2) included.
    const double ex = f.columnOf(m.dem.x0 + ei * m.dem.cell);
    const double ey = f.rowOf(m.dem.y0 + ej * m.dem.cell);
    EXPECT_TRUE(colourNear(im, ex, ey, 2, kRed)) << "outline side at " << ei << "," << ej;
  }
  const auto [ax, ay] = centre(10, 1);
  EXPECT_TRUE(colourNear(im, ax + 0.5, ay, 2, kRed)) << "line";
  const auto [px, py] = centre(16, 6);
  EXPECT_EQ(pixelAt(im, px, py), kRed) << "marker";
  const auto [ix, iy] = centre(3, 3);  // inside the outline: no fill
  EXPECT_FALSE(colourNear(im, ix, iy, 10, kRed));
  EXPECT_FALSE(colourNear(im, hx, hy, 10, kRed));
}

// Lines, barriers and the forest's edge each in their own colour, where their points say (the
// 1.5 px forest edge may be anti-aliased off its exact colour, so its own hue is looked for).
TEST(HazardMap, LinesBarriersAndTheForestEdgeLandWhereTheyLie) {
  test::ScratchDir dir("hazard_map_lines");
  const TestMap m;
  const auto at = [&](double i, double j) {
    return Vec2(m.dem.x0 + i * m.dem.cell, m.dem.y0 + j * m.dem.cell);
  };
  const std::vector<MapPolyline> polylines = {
      {{at(2, 12), at(6, 12)}, MapPolyline::Kind::kEvaluationLine},
      {{at(2, 8), at(6, 8)}, MapPolyline::Kind::kBarrier},
      {{at(12, 13), at(12, 15)}, MapPolyline::Kind::kForestEdge}};
  const std::string path = (dir.path() / "lines.png").string();
  writeHazardMap(m.dem, m.layer, {}, path, replaceOutputs(), {}, polylines);
  const Image im = readPng(path);
  const MapFrame f = hazardMapFrame(m.dem);
  const auto pixel = [&](double i, double j) {
    return std::pair{f.columnOf(m.dem.x0 + i * m.dem.cell), f.rowOf(m.dem.y0 + j * m.dem.cell)};
  };
  const auto [lx, ly] = pixel(4, 12);
  EXPECT_TRUE(colourNear(im, lx + 0.5, ly, 1, Rgb8{0x00, 0x72, 0xb2})) << "evaluation line";
  const auto [bx, by] = pixel(4, 8);
  EXPECT_TRUE(colourNear(im, bx + 0.5, by, 1, Rgb8{0, 0, 0})) << "barrier";
  const auto [fx, fy] = pixel(12, 14);
  bool green = false;
  for (int dx = -2; dx <= 2; ++dx) {
    const Rgb8 c = pixelAt(im, fx + dx, fy);
    green = green || (c.g > c.r + 40 && c.g > c.b + 40);
  }
  EXPECT_TRUE(green) << "forest edge";
  const auto [ox, oy] = pixel(16, 14);  // away from every line: no forest green
  const Rgb8 c = pixelAt(im, ox, oy);
  EXPECT_FALSE(c.g > c.r + 40 && c.g > c.b + 40);
}

TEST(HazardMap, TheAffectedWindowHoldsThePassedCellsAndReleasesWithAMargin) {
  const Heightfield dem = plane(100, 80, 1.0, -0.5, 0);
  std::vector<double> passages(dem.z.size(), 0.0);
  const auto cell = [&](int i, int j) -> double& {
    return passages[static_cast<std::size_t>(j) * dem.nx + i];
  };
  cell(40, 30) = cell(50, 35) = 2;
  // Box 40..50 x 30..35, a margin of 10 cells (a tenth of 11 is less).
  MapWindow w = affectedWindow(dem, passages, {});
  EXPECT_EQ(w.i0, 30);
  EXPECT_EQ(w.ni, 31);
  EXPECT_EQ(w.j0, 20);
  EXPECT_EQ(w.nj, 26);
  // A release point widens it (world x, y = sample index here: x0 = y0 = 0, 1 m cells).
  w = affectedWindow(dem, passages, {{Vec2(70.2, 60.4)}});
  EXPECT_EQ(w.i0 + w.ni - 1, 80);
  EXPECT_EQ(w.j0 + w.nj - 1, 70);
  // Within the grid.
  cell(2, 3) = cell(95, 78) = 1;
  w = affectedWindow(dem, passages, {});
  EXPECT_EQ(w.i0, 0);
  EXPECT_EQ(w.ni, 100);
  EXPECT_EQ(w.j0, 0);
  EXPECT_EQ(w.nj, 80);
  // Nothing passed, no release: the whole grid.
  EXPECT_EQ(affectedWindow(dem, std::vector<double>(dem.z.size(), 0.0), {}).ni, 0);
}

// A test map drawn: its picture, its layout, and the colour at the centre of sample (i, j).
struct DrawnMap {
  Image image;
  MapFrame frame;
  const Heightfield* dem = nullptr;
  Rgb8 at(int i, int j) const {
    return pixelAt(image, frame.columnOf(dem->x0 + i * dem->cell),
                   frame.rowOf(dem->y0 + j * dem->cell));
  }
};

DrawnMap draw(const TestMap& m, const std::string& name, const MapWindow& window = {}) {
  test::ScratchDir dir("hazard_map_" + name);
  const std::string path = (dir.path() / (name + ".png")).string();
  writeHazardMap(m.dem, m.layer, {}, path, replaceOutputs(), window);
  return {readPng(path), hazardMapFrame(m.dem, window), &m.dem};
}

TEST(HazardMap, AWindowedMapPutsItsValuesWhereItsLayoutSays) {
  const TestMap m;
  const MapWindow window{8, 4, 8, 10};  // samples 8..15 x 4..13: both marked cells
  const DrawnMap d = draw(m, "window", window);
  const MapFrame& f = d.frame;
  ASSERT_EQ(d.image.width, f.width);
  EXPECT_EQ(f.plotHeight, kMapLongSidePx);  // 8 x 10 samples: 640 x 800 px, 80 px a sample
  EXPECT_EQ(f.plotWidth, 640);
  EXPECT_DOUBLE_EQ(f.xMin, m.dem.x0 + 7.5 * m.dem.cell);
  EXPECT_EQ(d.at(TestMap::kHiI, TestMap::kHiJ), viridis(1.0));
  EXPECT_EQ(d.at(TestMap::kLoI, TestMap::kLoJ), viridis(0.0));
}

TEST(HazardMap, ALogScaledLayerColoursByTheLogarithmOfItsValue) {
  TestMap m;
  m.layer.logScale = true;
  // 4 .. 250 with 100 between: linear would put 100 at 0.39 of the map, log at 0.77; a value
  // of 0 or below takes the bottom colour and does not set the range.
  const std::size_t zeroCell = 2 * 20 + 2;
  m.layer.values[zeroCell] = 0;
  const DrawnMap d = draw(m, "log");
  EXPECT_EQ(d.at(TestMap::kHiI, TestMap::kHiJ), viridis(1.0));
  EXPECT_EQ(d.at(TestMap::kLoI, TestMap::kLoJ), viridis(0.0));
  EXPECT_EQ(d.at(TestMap::kLoI + 1, TestMap::kLoJ),
            viridis(std::log(100.0 / 4) / std::log(250.0 / 4)));
  EXPECT_EQ(d.at(2, 2), viridis(0.0));
  EXPECT_TRUE(mappedOnLogScale("reach_probability"));
  EXPECT_TRUE(mappedOnLogScale("energy_p95"));
  EXPECT_FALSE(mappedOnLogScale("height_p95"));
  EXPECT_FALSE(mappedOnLogScale("deposited"));
}

TEST(HazardMap, AClassedLayerColoursEachValueByItsClass) {
  TestMap m;  // 250 kJ, 4 kJ and 100 kJ
  m.layer.classes = swissRockfallIntensity();
  m.layer.values[2 * 20 + 2] = 300;  // on an edge: the class above
  m.layer.values[3 * 20 + 2] = 301;
  const DrawnMap d = draw(m, "classes");
  const MapClasses& k = m.layer.classes;
  EXPECT_EQ(d.at(TestMap::kLoI, TestMap::kLoJ), k.colours[0]);      // 4 kJ: low
  EXPECT_EQ(d.at(TestMap::kLoI + 1, TestMap::kLoJ), k.colours[1]);  // 100 kJ: medium
  EXPECT_EQ(d.at(TestMap::kHiI, TestMap::kHiJ), k.colours[1]);      // 250 kJ: medium
  EXPECT_EQ(d.at(2, 2), k.colours[2]);                              // 300 kJ: high
  EXPECT_EQ(d.at(2, 3), k.colours[2]);
  EXPECT_EQ(k.edges, (std::vector<double>{30.0, 300.0}));
}

TEST(HazardMap, PassingHeightClassesFollowTheirLimits) {
  const MapClasses two = passingHeightClasses({1.0, 2.0});
  EXPECT_EQ(two.edges, (std::vector<double>{1.0, 2.0}));
  EXPECT_EQ(two.labels, (std::vector<std::string>{"< 1 m", "1-2 m", "> 2 m"}));
  ASSERT_EQ(two.colours.size(), 3u);
  // Every count of limits: one colour per class, each darker than the one below it, so a
  // higher class never reads as a lower one.
  for (std::size_t n = 1; n <= 5; ++n) {
    const MapClasses c = passingHeightClasses(std::vector<double>(n, 1.0));
    ASSERT_EQ(c.colours.size(), n + 1) << n;
    ASSERT_EQ(c.labels.size(), n + 1) << n;
    for (std::size_t k = 1; k <= n; ++k)
      EXPECT_LT(lightness(c.colours[k]), lightness(c.colours[k - 1])) << n << " class " << k;
  }
  EXPECT_THROW(passingHeightClasses({}), std::invalid_argument);
  EXPECT_THROW(passingHeightClasses(std::vector<double>(6, 1.0)), std::invalid_argument);
  // On a map: 1 m lies on a limit and belongs to the class above it.
  TestMap m;
  m.layer.classes = two;
  m.layer.values[TestMap::kHiJ * 20 + TestMap::kHiI] = 2.5;
  m.layer.values[TestMap::kLoJ * 20 + TestMap::kLoI] = 0.4;
  m.layer.values[TestMap::kLoJ * 20 + TestMap::kLoI + 1] = 1.0;
  const DrawnMap d = draw(m, "heights");
  EXPECT_EQ(d.at(TestMap::kLoI, TestMap::kLoJ), two.colours[0]);
  EXPECT_EQ(d.at(TestMap::kLoI + 1, TestMap::kLoJ), two.colours[1]);
  EXPECT_EQ(d.at(TestMap::kHiI, TestMap::kHiJ), two.colours[2]);
}

TEST(HazardMap, AMapSmallerThanItsGridKeepsANarrowTrack) {
  // 1600 x 1200 samples on an 800 x 600 px map: two samples a pixel each way. A track one sample
  // wide (column 800, an even one: the sample under pixel 400's centre is 801) must still show,
  // at its highest value: a pixel shows the largest value it covers.
  test::ScratchDir dir("hazard_map_track");
  const Heightfield dem = plane(1600, 1200, 1.0, -0.5, 0);
  MapLayer layer{"passages", "Passages", "", std::vector<double>(dem.z.size(), std::nan(""))};
  for (int j = 0; j < dem.ny; ++j) layer.values[static_cast<std::size_t>(j) * dem.nx + 800] = 9;
  layer.values[100] = 0;
  const std::string path = (dir.path() / "track.png").string();
  writeHazardMap(dem, layer, {}, path);
  const MapFrame f = hazardMapFrame(dem);
  ASSERT_EQ(f.plotHeight, 600);
  const Image im = readPng(path);
  for (double y : {150.0, 600.0, 1050.0})
    EXPECT_EQ(pixelAt(im, f.columnOf(800), f.rowOf(y)), viridis(1.0)) << y;
}

TEST(HazardMap, SameInputSameBytes) {
  test::ScratchDir dir("hazard_map_bytes");
  const TestMap m;
  const auto bytes = [](const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
  };
  writeHazardMap(m.dem, m.layer, m.release, (dir.path() / "a.png").string());
  writeHazardMap(m.dem, m.layer, m.release, (dir.path() / "b.png").string());
  const std::string a = bytes(dir.path() / "a.png");
  EXPECT_GT(a.size(), 1000u);
  EXPECT_EQ(a, bytes(dir.path() / "b.png"));
}

TEST(HazardMap, EmptyAndConstantLayersStillDraw) {
  test::ScratchDir dir("hazard_map_empty");
  TestMap m;
  m.layer.values.assign(m.dem.z.size(), std::nan(""));
  const std::string path = (dir.path() / "empty.png").string();
  writeHazardMap(m.dem, m.layer, {}, path);
  const Image im = readPng(path);
  const MapFrame f = hazardMapFrame(m.dem);
  const auto [hx, hy] = std::pair{f.columnOf(m.dem.x0 + 14 * 5.0), f.rowOf(m.dem.y0 + 9 * 5.0)};
  const std::uint8_t* p = im.pixel(int(hx), int(hy));
  EXPECT_TRUE(p[0] == p[1] && p[1] == p[2]) << "hillshade only";
  m.layer.values.assign(m.dem.z.size(), 3.0);  // one value: the colour map's middle
  writeHazardMap(m.dem, m.layer, {}, path);
  EXPECT_EQ(pixelAt(readPng(path), hx, hy), viridis(0.5));
}

TEST(HazardMap, BadInputGivesInputErrorAndNoFile) {
  test::ScratchDir dir("hazard_map_errors");
  TestMap m;
  const fs::path good = dir.path() / "map.png";
  MapLayer shortLayer = m.layer;
  shortLayer.values.pop_back();
  EXPECT_THROW(writeHazardMap(m.dem, shortLayer, {}, good.string()), InputError);
  EXPECT_FALSE(fs::exists(good));
  // A "folder" that is a file: cannot be created, so nothing can be written there.
  std::ofstream(dir.path() / "plain_file") << "not a folder";
  const fs::path bad = dir.path() / "plain_file" / "map.png";
  try {
    writeHazardMap(m.dem, m.layer, m.release, bad.string());
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(bad.string()), std::string::npos) << e.what();
  }
  EXPECT_EQ(std::distance(fs::directory_iterator(dir.path()), fs::directory_iterator()), 1)
      << "only plain_file: no temporary left behind";
  // A missing folder is created, as for every voxfall output (render/output/output_file.h).
  const fs::path nested = dir.path() / "new" / "folder" / "map.png";
  writeHazardMap(m.dem, m.layer, m.release, nested.string());
  EXPECT_TRUE(fs::exists(nested));
}

TEST(RunoutPlot, WritesAPngOfTheStatedSize) {
  test::ScratchDir dir("runout_plot");
  std::vector<double> runout, angle;
  for (int k = 0; k < 200; ++k) {
    runout.push_back(300 + 2.5 * k);
    angle.push_back(38 - 0.05 * k);
  }
  runout.push_back(std::nan(""));  // left out
  angle.push_back(std::nan(""));
  const std::string path = (dir.path() / "runout.png").string();
  writeRunoutPlot(runout, angle, path);
  const Image im = readPng(path);
  EXPECT_EQ(im.width, kRunoutPlotWidthPx);
  EXPECT_EQ(im.height, kRunoutPlotHeightPx);
}

TEST(RunoutPlot, NoFiniteValueGivesInputErrorAndNoFile) {
  test::ScratchDir dir("runout_plot_errors");
  const fs::path path = dir.path() / "runout.png";
  EXPECT_THROW(writeRunoutPlot({std::nan("")}, {30.0}, path.string()), InputError);
  EXPECT_THROW(writeRunoutPlot({100.0}, {}, path.string()), InputError);
  EXPECT_FALSE(fs::exists(path));
}

// The README's example map (docs/img/tyrol_layout_example.png is this test's output,
// copied from the build folder): the Tyrol DEM placed as scenes/rockfall.toml places it, a
// synthetic layer (horizontal distance from the middle of the release line, on the ground below
// it) and the scene's release line and points.
TEST(HazardMap, TyrolExampleUsesTheDemFileCoordinates) {
  Heightfield dem =
      loadDem(std::string(VOXFALL_SOURCE_DIR) + "/scenes/terrain/tirol_avagar_dem.tif");
  shiftHeightfield(dem, Vec3(-247323.244194263, -350705.852927772, 0));
  const MapFrame f = hazardMapFrame(dem);
  ASSERT_TRUE(f.fileCoordinates);
  // gdalinfo: upper left (247320.745, 352637.456), lower right (249919.538, 350703.354).
  EXPECT_NEAR(f.xMin, 247320.745, 1e-3);
  EXPECT_NEAR(f.xMax, 249919.538, 1e-3);
  EXPECT_NEAR(f.yMin, 350703.354, 1e-3);
  EXPECT_NEAR(f.yMax, 352637.456, 1e-3);

  MapLayer layer{
      "distance_example", "Layout example (synthetic, not a simulation): distance", "m", {}};
  const Vec2 source(1200, 1230);
  for (int j = 0; j < dem.ny; ++j)
    for (int i = 0; i < dem.nx; ++i) {
      const Vec2 p(dem.x0 + i * dem.cell, dem.y0 + j * dem.cell);
      const double d = (p - source).norm();
      layer.values.push_back(dem.at(i, j) < 1690 && d < 900 && p.y() < 1230 ? d : std::nan(""));
    }
  const std::vector<std::vector<Vec2>> release = {
      {Vec2(1040, 1220), Vec2(1360, 1220), Vec2(1360, 1240), Vec2(1040, 1240)},
      {Vec2(1050, 1230)},
      {Vec2(1150, 1230)},
      {Vec2(1250, 1230)},
      {Vec2(1350, 1230)}};
  const fs::path out = fs::path(VOXFALL_BUILD_DIR) / "maps" / "tyrol_layout_example.png";
  writeHazardMap(dem, layer, release, out.string());
  const Image im = readPng(out.string());
  EXPECT_EQ(im.width, f.width);
  EXPECT_EQ(im.height, f.height);
  EXPECT_EQ(pixelAt(im, f.columnOf(1150), f.rowOf(1230)), kRed);
}

}  // namespace
}  // namespace vf

// Heightfield terrain: the ESRI ASCII grid reader, surface interpolation, and the sphere-tree
// collider, each against an independent oracle.
#include "sim/shape/heightfield.h"

#include <gtest/gtest.h>
#include <sys/resource.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <set>
#include <string>

#include "sim/collide/narrow_phase.h"
#include "sim/core/error.h"
#include "sim/core/prng.h"
#include "tests/support/test_world.h"

namespace vf {
namespace {

std::string writeGrid(const std::string& name, const std::string& text) {
  const auto dir = std::filesystem::temp_directory_path() / "voxfall_heightfield_test";
  std::filesystem::create_directories(dir);
  const auto path = dir / name;
  std::ofstream(path) << text;
  return path.string();
}

// A planar grid z = 0.3 x - 0.2 y + 1 sampled by hand, rows from the north.
std::string planeGrid(int nx, int ny, double cell, double x0, double y0, bool corner) {
  std::string s = "ncols " + std::to_string(nx) + "\nnrows " + std::to_string(ny) + "\n";
  s += std::string(corner ? "xllcorner " : "xllcenter ") + std::to_string(x0) + "\n";
  s += std::string(corner ? "yllcorner " : "yllcenter ") + std::to_string(y0) + "\n";
  s += "cellsize " + std::to_string(cell) + "\nNODATA_value -9999\n";
  const double sx = corner ? x0 + cell / 2 : x0, sy = corner ? y0 + cell / 2 : y0;
  for (int row = 0; row < ny; ++row) {
    const int j = ny - 1 - row;
    for (int i = 0; i < nx; ++i) {
      char buf[64];
      std::snprintf(buf, sizeof buf, "%.17g ", 0.3 * (sx + i * cell) - 0.2 * (sy + j * cell) + 1);
      s += buf;
    }
    s += "\n";
  }
  return s;
}

// 12 x 12 samples of 0.5 m from the origin, heights uniform in [0, 2], and a hole: sample 40,
// (4, 3), is NODATA, so its four cells, [1.5, 2.5] x [1, 2] m, have no surface.
Heightfield roughGrid(Prng& rng) {
  Heightfield rough;
  rough.nx = rough.ny = 12;
  rough.cell = 0.5;
  for (int s = 0; s < 144; ++s) rough.z.push_back(rng.uniform(0, 2));
  rough.z[40] = NAN;
  return rough;
}

// A random sphere over roughGrid's square [0, end]^2 or up to 0.5 m beside it, at most 3 m
// high: its centre, and its radius in r.
Vec3 sphereNear(Prng& rng, double end, double& r) {
  const double x = rng.uniform(-0.5, end + 0.5), y = rng.uniform(-0.5, end + 0.5);
  r = rng.uniform(0.01, 0.6);
  return Vec3(x, y, rng.uniform(0, 3));
}

TEST(Heightfield, ReadsCornerAndCentreHeadersWithRowsFromTheNorth) {
  for (bool corner : {true, false}) {
    const Heightfield h = loadDem(writeGrid("plane.asc", planeGrid(5, 4, 0.5, 10, 20, corner)));
    EXPECT_EQ(h.nx, 5);
    EXPECT_EQ(h.ny, 4);
    // xllcorner is the corner of the lower-left cell: its sample sits half a cell inside.
    EXPECT_DOUBLE_EQ(h.x0, corner ? 10.25 : 10.0);
    EXPECT_DOUBLE_EQ(h.y0, corner ? 20.25 : 20.0);
    for (int j = 0; j < 4; ++j)
      for (int i = 0; i < 5; ++i)
        EXPECT_NEAR(h.at(i, j), 0.3 * (h.x0 + i * 0.5) - 0.2 * (h.y0 + j * 0.5) + 1, 1e-12);
    // Linear interpolation on the two triangles of a cell is exact for a plane.
    Prng rng(5);
    for (int k = 0; k < 200; ++k) {
      const double x = rng.uniform(h.x0, h.x0 + 2.0), y = rng.uniform(h.y0, h.y0 + 1.5);
      EXPECT_NEAR(h.heightAt(x, y), 0.3 * x - 0.2 * y + 1, 1e-12);
      const Vec3 n = h.normalAt(x, y);
      EXPECT_NEAR(n.dot(Vec3(-0.3, 0.2, 1).normalized()), 1.0, 1e-12);
    }
    EXPECT_TRUE(std::isnan(h.heightAt(h.x0 - 0.01, h.y0)));  // outside the grid
    // The far edges belong to the last cells; just beyond them there is no surface.
    const double xEnd = h.x0 + 4 * 0.5, yEnd = h.y0 + 3 * 0.5;
    EXPECT_NEAR(h.heightAt(xEnd, yEnd), 0.3 * xEnd - 0.2 * yEnd + 1, 1e-12);
    EXPECT_NEAR(h.heightAt(xEnd, h.y0 + 0.3), 0.3 * xEnd - 0.2 * (h.y0 + 0.3) + 1, 1e-12);
    EXPECT_TRUE(std::isnan(h.heightAt(xEnd + 1e-9, h.y0 + 0.3)));
    EXPECT_TRUE(std::isnan(h.heightAt(h.x0 + 0.3, yEnd + 1e-9)));
    EXPECT_TRUE(std::isnan(h.heightAt(h.x0 - 1e30, h.y0)));  // far off: no overflowing index
  }
}

// cellIndex (the cell index of the heightfield and the diagnostics' cell grids) against
// std::floor then clamping, on both sides of every bound, and far off where a floor converted to
// int would overflow.
TEST(Heightfield, CellIndexIsTheClampedFloor) {
  for (double q : {-1.5, -1.0, -0.5, -0.0, 0.0, 0.25, 1.0, 2.999, 3.0, 4.5, 5.0, 5.5, 6.0})
    EXPECT_EQ(cellIndex(q, 5), std::clamp(static_cast<int>(std::floor(q)), 0, 5)) << q;
  EXPECT_EQ(cellIndex(-1e30, 5), 0);
  EXPECT_EQ(cellIndex(1e30, 5), 5);
  EXPECT_EQ(cellIndex(0.5, 0), 0);  // a single cell
}

// cellRange against counting cells one by one: cell i (of nx - 1) spans [x0 + i c, x0 + (i+1) c]
// and is in the range when its interior meets [x - r, x + r] (random squares, so none ends
// exactly on a grid line), the range clamped to the grid's cells; squares that miss the grid
// give an empty range. Squares straddle every edge of the grid and lie wholly beside it.
TEST(Heightfield, CellRangeIsTheCellsTheSquareMeets) {
  Heightfield h;
  h.nx = 9;
  h.ny = 6;
  h.cell = 0.7;
  h.x0 = -2.0;
  h.y0 = 3.0;
  h.z.assign(static_cast<std::size_t>(h.nx * h.ny), 1.0);
  auto count = [&](double lo, double hi, double origin, int cells, int& first, int& last) {
    first = cells, last = -1;
    for (int i = 0; i < cells; ++i)
      if (origin + (i + 1) * h.cell > lo && origin + i * h.cell < hi) {
        first = std::min(first, i);
        last = std::max(last, i);
      }
  };
  Prng rng(23);
  int empty = 0, clampedLow = 0, clampedHigh = 0;
  for (int k = 0; k < 2000; ++k) {
    const double x = rng.uniform(-4.5, 6.5), y = rng.uniform(0.5, 9.0), r = rng.uniform(0.05, 1.2);
    int i0, i1, j0, j1, a0, a1, b0, b1;
    h.cellRange(x, y, r, i0, i1, j0, j1);
    count(x - r, x + r, h.x0, h.nx - 1, a0, a1);
    count(y - r, y + r, h.y0, h.ny - 1, b0, b1);
    if (a1 < 0 || b1 < 0) {  // misses the grid
      ++empty;
      EXPECT_TRUE(i0 > i1 || j0 > j1) << x << " " << y << " " << r;
      continue;
    }
    clampedLow += x - r < h.x0 ? 1 : 0;
    clampedHigh += y + r > h.y0 + (h.ny - 1) * h.cell ? 1 : 0;
    EXPECT_EQ(i0, a0) << x << " " << r;
    EXPECT_EQ(i1, a1) << x << " " << r;
    EXPECT_EQ(j0, b0) << y << " " << r;
    EXPECT_EQ(j1, b1) << y << " " << r;
  }
  // The cases the clamping is for did occur.
  EXPECT_GT(empty, 100);
  EXPECT_GT(clampedLow, 100);
  EXPECT_GT(clampedHigh, 100);
}

TEST(Heightfield, NoDataCellsAreHoles) {
  const std::string grid =
      "ncols 3\nnrows 3\nxllcorner 0\nyllcorner 0\ncellsize 1\nNODATA_value -9999\n"
      "1 1 1\n1 -9999 1\n1 1 1\n";
  const Heightfield h = loadDem(writeGrid("hole.asc", grid));
  EXPECT_TRUE(std::isnan(h.at(1, 1)));
  EXPECT_FALSE(h.hasCell(0, 0));  // every cell touches the centre sample
  EXPECT_TRUE(std::isnan(h.heightAt(1.0, 1.0)));
  EXPECT_EQ(h.toMesh().triangles.size(), 0u);
  EXPECT_EQ(h.zMin, 1.0);
}

TEST(Heightfield, MalformedGridsNameFileAndLineFuzzFoundHugeCountsIncluded) {
  struct Case {
    std::string text, fragment;
  } cases[] = {
      {"ncols 2\nnrows 2\nxllcorner 0\nyllcorner 0\ncellsize 1\n1 2\n3\n", ":7: grid has 3 values"},
      {"ncols 2\nnrows 2\nxllcorner 0\nyllcorner 0\ncellsize 1\n1 2\n3 x\n",
       ":7: 'x' is not a number"},
      {"ncols 2\nnrows 2\nxllcorner 0\nyllcorner 0\ncellsize 0\n1 2\n3 4\n", "square cells"},
      {"ncols 2\nnrows 2\nxlcorner 0\nyllcorner 0\ncellsize 1\n1 2\n3 4\n",
       ":3: unknown header key 'xlcorner'"},
      {"ncols 2\nnrows 2\nxllcorner 0\nyllcorner 0\ncellsize 1\n1 2\n3 4 5\n", "more values than"},
      // From terrain_fuzz: a count beyond any grid (4e18 rows; its product with ncols would
      // overflow the conversion that prints it), and counts that are not whole or positive.
      {"ncols 60\nnrows 4075265075265407444.1\n4.4 2 3\n",
       ":2: header key 'nrows' must be a whole"},
      {"ncols 2.5\nnrows 2\nxllcorner 0\nyllcorner 0\ncellsize 1\n1 2\n3 4\n",
       ":1: header key 'ncols' must be a whole"},
      {"ncols 2\nnrows -2\nxllcorner 0\nyllcorner 0\ncellsize 1\n1 2\n3 4\n",
       ":2: header key 'nrows' must be a whole"},
  };
  for (const Case& c : cases) {
    const std::string path = writeGrid("bad.asc", c.text);
    try {
      loadDem(path);
      ADD_FAILURE() << "accepted: " << c.text;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(c.fragment), std::string::npos) << e.what();
    }
  }
  EXPECT_THROW(loadDem("/nonexistent/grid.asc"), InputError);
}

// From terrain_fuzz: a 383-byte file that GDAL's CTable2 driver (datum shift grids) reads as
// 235,802,126 x 235,802,126 samples, which loadDem would allocate unchecked. Any format's header
// may promise more than the file holds, so the size is checked before allocating. Here a
// 160-byte CTable2 header (16-byte magic, 80-byte id, four doubles, then width and height as
// little-endian int32) promises one column more than the limit of 2^28 samples.
std::string ctable2Header(std::int32_t width, std::int32_t height) {
  std::string header = "CTABLE V2.0     " + std::string(80, ' ');
  auto put = [&](const auto& value) {
    header.append(reinterpret_cast<const char*>(&value), sizeof value);
  };
  for (double v : {0.0, 0.0, 1e-5, 1e-5}) put(v);
  put(width);
  put(height);
  header.resize(160, '\0');
  return header;
}

TEST(Heightfield, FuzzFoundRasterHeaderPromisingTooManySamplesIsRefused) {
  static_assert(kMaxDemSamples == std::int64_t{16384} * 16384);
  const std::string path = writeGrid("huge.ct2", ctable2Header(16385, 16384));
  try {
    loadDem(path);
    ADD_FAILURE() << "accepted a raster of 16385 x 16384 samples";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("16385 x 16384 samples, more than voxfall's limit of "
                                         "268435456"),
              std::string::npos)
        << e.what();
  }
}

// A raster within the limit that the machine cannot hold: one message naming the file, not
// std::bad_alloc. The limit's own 16384 x 16384 (2 GiB of heights) in a child process whose
// address space is capped at 1 GiB. Not under AddressSanitizer, whose shadow memory needs
// terabytes of address space.
#if defined(__SANITIZE_ADDRESS__)
#define VF_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define VF_ASAN 1
#endif
#endif
TEST(Heightfield, RasterTooLargeForMemoryIsAnInputError) {
#ifdef VF_ASAN
  GTEST_SKIP() << "address-space cap and AddressSanitizer exclude each other";
#else
  GTEST_FLAG_SET(death_test_style, "threadsafe");
  const std::string path = writeGrid("limit.ct2", ctable2Header(16384, 16384));
  // In the child: 0 for the message, 2 for another error, 3 for none.
  auto loadUnderCap = [&path] {
    const rlimit cap{std::uint64_t{1} << 30, std::uint64_t{1} << 30};
    setrlimit(RLIMIT_AS, &cap);
    try {
      loadDem(path);
    } catch (const InputError& e) {
      const std::string what = e.what();
      const bool named = what.find(path) != std::string::npos &&
                         what.find(
                             "not enough memory for the terrain raster's 16384 x 16384 "
                             "samples") != std::string::npos;
      std::exit(named ? 0 : 2);
    }
    std::exit(3);
  };
  EXPECT_EXIT(loadUnderCap(), testing::ExitedWithCode(0), "");
#endif
}

TEST(Heightfield, ReadsTheRealTschamutTerrain) {
  // Real grid: 43 x 46 cells of 5 m (header of tests/data/tschamut2014_terrain_proxy_5m.asc).
  const Heightfield h = loadDem(VOXFALL_TEST_DATA_DIR "/tschamut2014_terrain_proxy_5m.asc");
  EXPECT_EQ(h.nx, 43);
  EXPECT_EQ(h.ny, 46);
  EXPECT_DOUBLE_EQ(h.cell, 5.0);
  EXPECT_DOUBLE_EQ(h.x0, -35.0 + 2.5);
  // The file's first value (north-west sample) is 125.494105.
  EXPECT_DOUBLE_EQ(h.at(0, h.ny - 1), 125.494105);
  EXPECT_LT(h.zMin, h.zMax);
}

TEST(Heightfield, ReadsTheTyrolDemWithCentreHeaderAndNoData) {
  // scenes/terrain/tirol_avagar_dem.tif is the AvaFrame avaGar ESRI ASCII grid (xllcenter
  // header, NODATA -9999) converted losslessly to a Float64 GeoTIFF. Oracle values from the
  // ASCII original with awk: xllcenter 247323.244194263, yllcenter 350705.852927772, cellsize
  // 4.997678230579; row 100 from the north, column 300 holds 1643.325439453125; 82888 values
  // are -9999.
  const Heightfield h = loadDem(VOXFALL_SOURCE_DIR "/scenes/terrain/tirol_avagar_dem.tif");
  EXPECT_EQ(h.nx, 520);
  EXPECT_EQ(h.ny, 387);
  EXPECT_NEAR(h.x0, 247323.244194263, 1e-6);
  EXPECT_NEAR(h.y0, 350705.852927772, 1e-6);
  EXPECT_NEAR(h.cell, 4.997678230579, 1e-12);
  EXPECT_EQ(h.at(300, h.ny - 1 - 100), 1643.325439453125);
  EXPECT_EQ(std::count_if(h.z.begin(), h.z.end(), [](double v) { return std::isnan(v); }), 82888);
}

TEST(Heightfield, GeoTiffAndAsciiGiveTheSameGridAndTheTiffKeepsItsCrs) {
  // The same planar grid as ESRI ASCII and as a GeoTIFF written by gdal_translate (gdal-bin)
  // with a CRS assigned: same samples, same georeference, CRS kept.
  const std::string asc = writeGrid("same.asc", planeGrid(6, 5, 2.0, 1000, 2000, true));
  const std::string tif = asc.substr(0, asc.size() - 4) + ".tif";
  ASSERT_EQ(
      std::system(
          ("gdal_translate -q -oo DATATYPE=Float64 -a_srs EPSG:31287 " + asc + " " + tif).c_str()),
      0);
  const Heightfield a = loadDem(asc), t = loadDem(tif);
  EXPECT_EQ(t.nx, a.nx);
  EXPECT_EQ(t.ny, a.ny);
  EXPECT_EQ(t.x0, a.x0);
  EXPECT_EQ(t.y0, a.y0);
  EXPECT_EQ(t.cell, a.cell);
  EXPECT_EQ(t.z, a.z);
  EXPECT_TRUE(a.crsWkt.empty());  // an .asc without .prj has none
  EXPECT_NE(t.crsWkt.find("Austria Lambert"), std::string::npos) << t.crsWkt;
  EXPECT_EQ(t.crsName, "EPSG:31287");
}

// Collides `body` with the terrain and with `plane`: both must give the same leaf spheres, the
// terrain's contacts with the plane's normal and a positive depth. Returns whether any touched.
bool sameLeavesAsPlane(const Collider& body, const Heightfield& h, const Collider& plane,
                       const std::string& trial) {
  std::vector<Contact> viaTerrain, viaPlane;
  collide(body, heightfieldCollider(h), viaTerrain);
  collide(body, plane, viaPlane);
  std::set<std::uint32_t> a, b;
  for (const Contact& c : viaTerrain) {
    a.insert(c.leafA);
    EXPECT_NEAR(c.normal.dot(plane.normal), 1.0, 1e-9) << trial;
    EXPECT_GT(c.depth, 0) << trial;
  }
  for (const Contact& c : viaPlane) b.insert(c.leafA);
  EXPECT_EQ(a, b) << trial;
  return !a.empty();
}

// Oracle: on a planar grid, the terrain collider must find exactly the leaf spheres that a
// tilted infinite plane finds (for a body well inside the grid), with the plane's normal.
TEST(Heightfield, ColliderMatchesATiltedPlaneOnAPlanarGrid) {
  const Heightfield h = loadDem(writeGrid("tilt.asc", planeGrid(30, 30, 0.25, -3.75, -3.75, true)));
  const Vec3 n = Vec3(-0.3, 0.2, 1).normalized();  // upward normal of z = 0.3x - 0.2y + 1
  Collider plane;
  plane.type = ColliderType::kPlane;
  plane.normal = n;
  plane.offset = n.dot(Vec3(0, 0, 1));  // the point (0, 0, 1) lies on it
  auto s = test::boxShape(0.4, 0.3, 0.2, 800, 4);
  Prng rng(11);
  int withContacts = 0;
  for (int trial = 0; trial < 40; ++trial) {
    const Vec3 x(rng.uniform(-1, 1), rng.uniform(-1, 1), 0);
    const Quat q =
        Quat(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1))
            .normalized();
    const Vec3 pos(x.x(), x.y(), 0.3 * x.x() - 0.2 * x.y() + 1 + rng.uniform(-0.15, 0.3));
    const Collider body = sphereTreeCollider(0, *s->tree, pos, q);
    withContacts += sameLeavesAsPlane(body, h, plane, "trial " + std::to_string(trial));
  }
  EXPECT_GT(withContacts, 10);
}

// Oracle: the terrain is solid below its surface, so beside a flat grid 2 m high (4 x 4 m,
// nothing around it) and below its top, each border is the vertical plane through it: the
// collider must find exactly the leaf spheres that the plane collider finds, with the plane's
// outward normal (no contacts at all before the border wall existed).
TEST(Heightfield, BesideTheGridItsBorderIsAVerticalWall) {
  const Heightfield h = test::flatHeightfield(9, 9, 0.5, 2.0);
  auto s = test::boxShape(0.2, 0.15, 0.1, 800, 2);
  const SphereTreeLevel& leaves = s->tree->leaves();
  const Vec3 outward[4] = {-Vec3::UnitX(), Vec3::UnitX(), -Vec3::UnitY(), Vec3::UnitY()};
  Prng rng(5);
  int withContacts = 0;
  for (int trial = 0; trial < 40; ++trial) {
    const Vec3& n = outward[trial % 4];
    const Quat q =
        Quat(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1))
            .normalized();
    // How far the box's leaf centres reach towards the grid from its centre.
    double reach = 0;
    for (const Vec3& c : leaves.centers) reach = std::max(reach, -n.dot(q * c));
    // A point on the border (x or y is 0 or 4), then the box's centre outside it by `reach`
    // plus up to one leaf radius, so every leaf centre is outside the grid and the nearest
    // leaves may touch the wall, at 0.5-1.5 m, below the top.
    const double along = rng.uniform(1, 3);
    const Vec3 onBorder =
        n.x() != 0 ? Vec3(n.x() < 0 ? 0 : 4, along, 0) : Vec3(along, n.y() < 0 ? 0 : 4, 0);
    const Vec3 pos = onBorder + (reach + rng.uniform(1e-6, leaves.radius)) * n +
                     Vec3(0, 0, rng.uniform(0.5, 1.5));
    const Collider body = sphereTreeCollider(0, *s->tree, pos, q);
    Collider wall;
    wall.type = ColliderType::kPlane;
    wall.normal = n;
    wall.offset = n.dot(onBorder);
    withContacts += sameLeavesAsPlane(body, h, wall, "trial " + std::to_string(trial));
  }
  EXPECT_GT(withContacts, 10);
}

// surfaceBoundNear (the terrain narrow phase's pruning bound). Oracles: on the planar grid
// z = 0.3x - 0.2y + 1 it is the plane's maximum over the square, at its corner (x + r, y - r),
// up to its 1e-9 m margin and rounding; on a rough grid it is never below the surface at any
// point of the square (dense sampling) and never above maxHeightNear.
TEST(Heightfield, SurfaceBoundIsThePlanesMaximumAndNeverBelowARoughSurface) {
  const Heightfield tilt =
      loadDem(writeGrid("tilt_bound.asc", planeGrid(30, 30, 0.25, -3.75, -3.75, true)));
  Prng rng(17);
  for (int k = 0; k < 200; ++k) {
    const double x = rng.uniform(-3, 3), y = rng.uniform(-3, 3), r = rng.uniform(0.01, 0.6);
    EXPECT_NEAR(tilt.surfaceBoundNear(x, y, r), 0.3 * (x + r) - 0.2 * (y - r) + 1, 2e-9);
  }
  const Heightfield rough = roughGrid(rng);
  for (int k = 0; k < 200; ++k) {
    const double x = rng.uniform(-0.5, 6), y = rng.uniform(-0.5, 6), r = rng.uniform(0.01, 0.6);
    const double bound = rough.surfaceBoundNear(x, y, r);
    EXPECT_LE(bound, rough.maxHeightNear(x, y, r) + 1e-9);
    for (int a = 0; a <= 20; ++a)
      for (int b = 0; b <= 20; ++b) {
        const double h = rough.heightAt(x - r + 0.1 * a * r, y - r + 0.1 * b * r);
        if (!std::isnan(h)) {
          EXPECT_LE(h, bound) << x << " " << y << " " << r;
        }
      }
  }
}

// The plane test of surfaceBoundNear (the terrain descent's second pruning test). Oracles: on the
// planar grid z = 0.3x - 0.2y + 1 the distance to the surface is the distance to the plane, (z -
// plane) / sqrt(1 + 0.3^2 + 0.2^2): a sphere 1.001 radii from it is clear and one 0.999 radii from
// it is not, where the bound decides nothing (the plane's maximum over the square is higher than
// the sphere's lowest point), and the bound is the one without the test. On a rough grid with a
// hole, and beside its border (the wall), a sphere it calls clear has its centre above the surface
// and no surface or wall point within r by dense sampling; and it calls some spheres clear, some
// not.
TEST(Heightfield, ClearOfThePlanesMeansNoSurfaceWithinTheRadius) {
  const Heightfield tilt =
      loadDem(writeGrid("tilt_clear.asc", planeGrid(30, 30, 0.25, -3.75, -3.75, true)));
  const double slope = std::sqrt(1 + 0.3 * 0.3 + 0.2 * 0.2);
  Prng rng(23);
  for (int k = 0; k < 200; ++k) {
    const double x = rng.uniform(-3, 3), y = rng.uniform(-3, 3), r = rng.uniform(0.01, 0.6);
    const double plane = 0.3 * x - 0.2 * y + 1;
    const Vec3 clear(x, y, plane + 1.001 * r * slope), near(x, y, plane + 0.999 * r * slope);
    bool isClear = false, nearIsClear = true;
    const double bound = tilt.surfaceBoundNear(clear, r, isClear);
    tilt.surfaceBoundNear(near, r, nearIsClear);
    EXPECT_TRUE(isClear) << x << " " << y << " " << r;
    EXPECT_FALSE(nearIsClear) << x << " " << y << " " << r;
    EXPECT_EQ(bound, tilt.surfaceBoundNear(x, y, r));
    EXPECT_LT(clear.z() - r, bound);  // the bound alone keeps it
  }

  const Heightfield rough = roughGrid(rng);
  const double end = 0.5 * 11;
  int clear = 0, notClear = 0;
  for (int k = 0; k < 600; ++k) {
    double r;
    const Vec3 c = sphereNear(rng, end, r);
    const double x = c.x(), y = c.y(), z = c.z();
    bool isClear = false;
    const double bound = rough.surfaceBoundNear(c, r, isClear);
    EXPECT_EQ(bound, rough.surfaceBoundNear(x, y, r));
    if (!isClear) {
      ++notClear;
      continue;
    }
    ++clear;
    const double under = rough.heightAt(x, y);
    if (!std::isnan(under)) {
      EXPECT_GT(z, under) << x << " " << y << " " << r;
    }
    for (int a = 0; a <= 30; ++a)
      for (int b = 0; b <= 30; ++b) {
        const double px = x - r + a * r / 15, py = y - r + b * r / 15;
        const double h = rough.heightAt(px, py);
        if (!std::isnan(h)) {
          EXPECT_GT((Vec3(px, py, h) - c).norm(), r) << x << " " << y << " " << r;
        }
        // The border wall: below the surface line of the nearest border point.
        const Vec3 onBorder(std::clamp(px, 0.0, end), std::clamp(py, 0.0, end), 0);
        if (onBorder.x() == px && onBorder.y() == py) continue;  // inside the grid
        const double top = rough.heightAt(onBorder.x(), onBorder.y());
        if (std::isnan(top)) continue;
        for (int w = 0; w <= 10; ++w) {
          const Vec3 wall(onBorder.x(), onBorder.y(), top - 0.2 * w);
          EXPECT_GT((wall - c).norm(), r) << x << " " << y << " " << r;
        }
      }
  }
  EXPECT_GT(clear, 60);
  EXPECT_GT(notClear, 60);
}

// One cell of 1 m folded into a ridge along its diagonal (p00 and p11 at z = 1, p10 and p01 at
// 0): over the first triangle the second's extended plane rises above the surface, the case
// where the plane test alone keeps spheres that are far from the surface.
Heightfield ridgeCell() {
  Heightfield h;
  h.nx = h.ny = 2;
  h.cell = 1;
  h.z = {1, 0, 0, 1};  // z[j * nx + i]: (0,0), (1,0), (0,1), (1,1)
  return h;
}

// The plane test decides by the triangles the square reaches. Oracle: by hand on the ridge
// cell (planes z = 1 - u + v over u >= v and z = 1 + u - v over u <= v, cell units = m). A
// sphere of r = 0.1 at (0.9, 0.1), 0.3 above the first triangle (0.173 from its plane), has a
// square that misses the second triangle: clear, although it lies 1.3 below the second's
// extended plane. A sphere of r = 0.05 at (0.55, 0.45, 1.05), 0.15 above the first triangle,
// has a square that reaches both, and lies below the second's plane (1.1 there) and under the
// cell's highest sample: not clear by the planes, yet 0.087 from the nearest surface point, the
// ridge point (0.5, 0.5, 1): sphereAbove, the exact test, says so.
TEST(Heightfield, PlaneTestIgnoresATriangleTheSquareMisses) {
  const Heightfield ridge = ridgeCell();
  bool clear = false;
  ridge.surfaceBoundNear(Vec3(0.9, 0.1, 0.2 + 0.3), 0.1, clear);
  EXPECT_TRUE(clear);
  ridge.surfaceBoundNear(Vec3(0.9, 0.1, 0.2 + 0.15), 0.1, clear);  // 0.087 from its plane
  EXPECT_FALSE(clear);
  // The bound over the square [0.8, 1] x [0, 0.2] is the first plane's maximum, at (0.8, 0.2).
  EXPECT_NEAR(ridge.surfaceBoundNear(0.9, 0.1, 0.1), 1 - 0.8 + 0.2, 2e-9);
  const Vec3 nearRidge(0.55, 0.45, 1.05);
  ridge.surfaceBoundNear(nearRidge, 0.05, clear);
  EXPECT_FALSE(clear);
  EXPECT_TRUE(ridge.sphereAbove(nearRidge, 0.05));
}

// sphereAbove (the terrain descent's exact pruning test for inner nodes). Oracles: the ridge
// cell by hand; and on a rough grid with a hole, brute force over every triangle of the grid:
// a sphere it calls above has its centre above the surface, every triangle farther than r, its
// square inside the grid and no hole under it. It must also drop spheres that the plane test
// keeps (its reason to exist).
TEST(Heightfield, SphereAboveMeansNoTriangleWithinTheRadius) {
  const Heightfield ridge = ridgeCell();
  const Vec3 nearRidge(0.55, 0.45, 1.05);
  EXPECT_TRUE(ridge.sphereAbove(nearRidge, 0.085));
  EXPECT_FALSE(ridge.sphereAbove(nearRidge, 0.088)) << "the ridge point is 0.0866 away";
  EXPECT_FALSE(ridge.sphereAbove(Vec3(0.55, 0.45, 0.85), 0.01)) << "below the surface";
  EXPECT_FALSE(ridge.sphereAbove(Vec3(0.9, 0.1, 5), 0.2)) << "the square reaches the border";

  Prng rng(29);
  const Heightfield rough = roughGrid(rng);
  const TriMesh mesh = rough.toMesh();
  const double end = 0.5 * 11;
  int above = 0, aboveOnly = 0;
  for (int k = 0; k < 2000; ++k) {
    double r;
    const Vec3 c = sphereNear(rng, end, r);
    const double x = c.x(), y = c.y(), z = c.z();
    bool isClear = false;
    rough.surfaceBoundNear(c, r, isClear);
    const bool isAbove = rough.sphereAbove(c, r);
    aboveOnly += isAbove && !isClear;
    if (!isAbove) continue;
    ++above;
    EXPECT_TRUE(x - r > 0 && y - r > 0 && x + r < end && y + r < end) << x << " " << y;
    EXPECT_GT(z, rough.heightAt(x, y)) << x << " " << y << " " << r;
    double nearest = INFINITY;
    for (const auto& t : mesh.triangles)
      nearest =
          std::min(nearest, (closestPointOnTriangle(c, mesh.vertices[t[0]], mesh.vertices[t[1]],
                                                    mesh.vertices[t[2]]) -
                             c)
                                .norm());
    EXPECT_GT(nearest, r) << x << " " << y << " " << r;
    // No hole under the square (roughGrid).
    EXPECT_FALSE(x + r >= 1.5 && x - r <= 2.5 && y + r >= 1 && y - r <= 2) << x << " " << y;
  }
  EXPECT_GT(above, 100);
  EXPECT_GT(aboveOnly, 20) << "spheres the planes keep and the exact test drops";
}

// minNormalZNear (clearOfGround's bound on the normals under a body). Oracles: on the planar
// grid z = 0.3x - 0.2y + 1 every normal's z is 1 / sqrt(1 + 0.3^2 + 0.2^2); on ridges of unit
// slope (z = 1 where i + j is even) every triangle's is 1 / sqrt(3); level ground gives 1; on a
// rough grid with a hole, the least over the triangles of toMesh whose cells meet the square.
TEST(Heightfield, MinNormalZIsTheSteepestFacetsUnderTheSquare) {
  const Heightfield tilt =
      loadDem(writeGrid("tilt_normal.asc", planeGrid(30, 30, 0.25, -3.75, -3.75, true)));
  EXPECT_NEAR(tilt.minNormalZNear(0.1, 0.2, 0.6), 1 / std::sqrt(1 + 0.09 + 0.04), 1e-12);
  Heightfield ridges;
  ridges.nx = ridges.ny = 4;
  ridges.cell = 1;
  for (int j = 0; j < 4; ++j)
    for (int i = 0; i < 4; ++i) ridges.z.push_back((i + j) % 2 == 0 ? 1.0 : 0.0);
  EXPECT_NEAR(ridges.minNormalZNear(1.5, 1.5, 0.2), 1 / std::sqrt(3.0), 1e-12);
  EXPECT_EQ(test::flatHeightfield(5, 5, 1.0, 0.3).minNormalZNear(2, 2, 1), 1.0);
  Prng rng(31);
  const Heightfield rough = roughGrid(rng);
  const TriMesh mesh = rough.toMesh();  // two triangles per cell with data, cells in row order
  for (int k = 0; k < 100; ++k) {
    const double x = rng.uniform(0, 5.5), y = rng.uniform(0, 5.5), r = rng.uniform(0.01, 0.6);
    double least = 1;
    for (const auto& t : mesh.triangles) {
      const Vec3 &a = mesh.vertices[t[0]], &b = mesh.vertices[t[1]], &c = mesh.vertices[t[2]];
      // The cell of the triangle: its south-west corner is the lowest x and y of its vertices.
      const double cx = std::min({a.x(), b.x(), c.x()}), cy = std::min({a.y(), b.y(), c.y()});
      if (cx > x + r || cx + 0.5 < x - r || cy > y + r || cy + 0.5 < y - r) continue;
      least = std::min(least, (b - a).cross(c - a).normalized().z());
    }
    EXPECT_NEAR(rough.minNormalZNear(x, y, r), least, 1e-15) << x << " " << y << " " << r;
  }
}

TEST(Heightfield, ClosestPointOnTriangleAgreesWithDenseSampling) {
  Prng rng(2);
  const Vec3 a(0, 0, 0), b(1, 0, 0.2), c(0.3, 0.8, -0.1);
  for (int k = 0; k < 100; ++k) {
    const Vec3 p(rng.uniform(-1, 2), rng.uniform(-1, 2), rng.uniform(-1, 1));
    const double d = (closestPointOnTriangle(p, a, b, c) - p).norm();
    double best = INFINITY;
    for (int i = 0; i <= 200; ++i)
      for (int j = 0; i + j <= 200; ++j) {
        const Vec3 q = a + (b - a) * (i / 200.0) + (c - a) * (j / 200.0);
        best = std::min(best, (q - p).norm());
      }
    // The sampling grid is 1/200 of the edges (<= 1.1 m): the sampled minimum exceeds the true
    // one by at most half a grid diagonal, ~0.0055 m; it can never be smaller.
    EXPECT_LE(d, best + 1e-12);
    EXPECT_GE(d, best - 0.006);
  }
}

}  // namespace
}  // namespace vf

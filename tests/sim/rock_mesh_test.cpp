// Generated rocks (sim/geometry/rock_mesh.h) and the convex hull under them.
//
// Oracles: the EOTA block's vertices written out by hand; its volume and inertia from a
// cross-section sweep of its half-space form, an integral independent of the mesh and of the
// divergence theorem; membership of random points in that half-space form against the mesh;
// for natural rocks, closedness, convexity (every vertex behind every face plane) and the
// extents, ratios and volumes each class promises, checked on the mesh itself.
#include "sim/geometry/rock_mesh.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <map>
#include <set>
#include <tuple>

#include "sim/core/error.h"
#include "sim/core/hash.h"
#include "sim/core/prng.h"
#include "sim/geometry/convex_hull.h"
#include "sim/geometry/mass_properties.h"
#include "sim/geometry/mesh_checks.h"
#include "sim/geometry/mesh_query.h"

namespace vf {
namespace {

using Key = std::tuple<double, double, double>;

std::set<Key> vertexSet(const TriMesh& m) {
  std::set<Key> out;
  for (const Vec3& v : m.vertices) out.emplace(v.x(), v.y(), v.z());
  return out;
}

// Distinct planes of the triangles: unit normal and offset, rounded to 1e-9 so that the two
// triangles of one face (same plane up to round-off) count once.
std::size_t facePlanes(const TriMesh& m) {
  std::set<std::array<long long, 4>> planes;
  for (const auto& t : m.triangles) {
    const Vec3 a = m.vertices[t[0]], b = m.vertices[t[1]], c = m.vertices[t[2]];
    const Vec3 n = (b - a).cross(c - a).normalized();
    const auto r = [](double x) { return std::llround(x * 1e9); };
    planes.insert({r(n.x()), r(n.y()), r(n.z()), r(n.dot(a))});
  }
  return planes.size();
}

// The largest distance of a vertex in front of a face's plane (> 0: not convex), relative to
// the mesh's size.
double worstConvexity(const TriMesh& m) {
  const double size = m.bounds().sizes().maxCoeff();
  double worst = -1;
  for (const auto& t : m.triangles) {
    const Vec3 a = m.vertices[t[0]], b = m.vertices[t[1]], c = m.vertices[t[2]];
    const Vec3 n = (b - a).cross(c - a).normalized();
    for (const Vec3& v : m.vertices) worst = std::max(worst, n.dot(v - a) / size);
  }
  return worst;
}

std::uint64_t meshHash(const TriMesh& m) {
  Hasher h;
  for (const Vec3& v : m.vertices)
    for (int k = 0; k < 3; ++k) h.add(v[k]);
  for (const auto& t : m.triangles)
    for (std::uint32_t i : t) h.add(static_cast<std::uint64_t>(i));
  return h.value();
}

RockDef rock(const std::string& shapeClass, std::uint64_t seed, double volume) {
  RockDef d;
  d.shapeClass = shapeClass;
  d.seed = seed;
  d.volume = volume;
  return d;
}

// --- the EOTA block ----------------------------------------------------------------------------

// Volume and second moment <x^2> (per unit volume) of the EOTA 111 block of edge 1, from its
// half-space form |x|, |y|, |z| <= 1/2; |x|+|y|, |y|+|z|, |x|+|z| <= 3/4; |x|+|y|+|z| <= 1
// (rockfall-models.md 9.5), by sweeping the octant x, y, z >= 0 in x. The section at x is the
// square [0, m]^2 less the corner where y + z > s:
//   x in [0, 1/4]:   m = 1/2, s = 3/4 (x + y <= 3/4 and x + y + z <= 1 do not bind):
//                    A = 1/4 - (1/4)^2 / 2 = 7/32;
//   x = 1/4 + t, t in [0, 1/4]: m = 1/2 - t (from x + y <= 3/4), s = 3/4 - t (from
//                    x + y + z <= 1), corner legs 2m - s = 1/4 - t:
//                    A = (1/2 - t)^2 - (1/4 - t)^2 / 2.
// A(x) and x^2 A(x) are polynomials of degree <= 4 on each piece, which 3-point Gauss-Legendre
// integrates exactly. The result is 17/24 and 21/340.
void eotaSweep(double& volume, double& meanX2) {
  const double node = std::sqrt(0.6), w[3] = {5.0 / 9, 8.0 / 9, 5.0 / 9};
  const double u[3] = {-node, 0, node};
  double v = 0, x2 = 0;
  for (int piece = 0; piece < 2; ++piece)
    for (int k = 0; k < 3; ++k) {
      const double x = piece * 0.25 + 0.125 * (1 + u[k]);  // [piece/4, piece/4 + 1/4]
      const double t = x - 0.25;
      const double area =
          piece == 0 ? 7.0 / 32 : (0.5 - t) * (0.5 - t) - (0.25 - t) * (0.25 - t) / 2;
      v += 0.125 * w[k] * area;
      x2 += 0.125 * w[k] * x * x * area;
    }
  volume = 8 * v;
  meanX2 = x2 / v;
}

bool insideEotaForm(const Vec3& p, double L) {
  const Vec3 a = p.cwiseAbs() / L;
  return a.maxCoeff() <= 0.5 && a.x() + a.y() <= 0.75 && a.y() + a.z() <= 0.75 &&
         a.x() + a.z() <= 0.75 && a.sum() <= 1;
}

TEST(RockMesh, EotaSweepGivesTheExactConstants) {
  // The oracle below, against the fractions the sweep works out to by hand.
  double volume = 0, meanX2 = 0;
  eotaSweep(volume, meanX2);
  EXPECT_NEAR(volume, 17.0 / 24, 1e-15);
  EXPECT_NEAR(meanX2, 21.0 / 340, 1e-15);
}

TEST(RockMesh, Eota111HasTheTwentyFourVerticesAndTwentySixFaces) {
  const double L = 0.8;
  RockDef d;
  d.shapeClass = "eota_111";
  d.length = L;
  TriMesh m = makeRockMesh(d);
  std::set<Key> want;
  const double h = L / 2, q = L / 4;  // exact: halving a double
  for (double sx : {-1.0, 1.0})
    for (double sy : {-1.0, 1.0})
      for (double sz : {-1.0, 1.0}) {
        want.emplace(sx * h, sy * q, sz * q);
        want.emplace(sx * q, sy * h, sz * q);
        want.emplace(sx * q, sy * q, sz * h);
      }
  ASSERT_EQ(want.size(), 24u);
  EXPECT_EQ(m.vertices.size(), 24u);
  EXPECT_EQ(vertexSet(m), want);  // bit for bit
  EXPECT_EQ(facePlanes(m), 26u);  // 6 squares, 12 rectangles, 8 triangles
  EXPECT_NO_THROW(validateClosedMesh(m, "eota_111"));
}

TEST(RockMesh, Eota111VolumeAndInertiaAreTheSweepsExactValues) {
  const double L = 1.3, rho = 2700;
  RockDef d;
  d.shapeClass = "eota_111";
  d.length = L;
  const MassProperties mp = computeMassProperties(makeRockMesh(d), rho);
  double unitVolume = 0, meanX2 = 0;
  eotaSweep(unitVolume, meanX2);
  // 17/24 L^3 and I = 2 <x^2> m L^2 = 21/170 m L^2 about every axis, no products of inertia
  // (the block's symmetry). The mesh's sums have a few dozen terms of the result's size: 1e-13.
  const double V = unitVolume * L * L * L, m = rho * V, I = 2 * meanX2 * m * L * L;
  EXPECT_NEAR(mp.volume, V, 1e-13 * V);
  EXPECT_NEAR(I / (m * L * L), 21.0 / 170, 1e-15);
  EXPECT_NEAR(21.0 / 170, 0.1236, 0.5e-2 * 0.1236);  // rockfall-models.md's numeric +-0.5 %
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      EXPECT_NEAR(mp.inertia(i, j), i == j ? I : 0.0, 1e-13 * I) << i << ", " << j;
  EXPECT_LE(mp.centerOfMass.norm(), 1e-15 * L);
}

TEST(RockMesh, Eota111MeshIsItsHalfSpaceForm) {
  const double L = 1.0;
  RockDef d;
  d.shapeClass = "eota_111";
  d.length = L;
  const TriMesh m = makeRockMesh(d);
  Prng rng(11);
  int inside = 0;
  for (int k = 0; k < 4000; ++k) {
    const Vec3 p(rng.uniform(-0.55, 0.55), rng.uniform(-0.55, 0.55), rng.uniform(-0.55, 0.55));
    // Points within 1e-9 of a bounding plane could go either way by rounding: skip them.
    const Vec3 a = p.cwiseAbs();
    const double margin = std::min({std::abs(a.maxCoeff() - 0.5), std::abs(a.x() + a.y() - 0.75),
                                    std::abs(a.y() + a.z() - 0.75), std::abs(a.x() + a.z() - 0.75),
                                    std::abs(a.sum() - 1)});
    if (margin < 1e-9) continue;
    const bool want = insideEotaForm(p, L);
    inside += want;
    EXPECT_EQ(pointInsideMesh(m, p), want) << p.transpose();
  }
  EXPECT_GT(inside, 1000);  // both answers were tested
}

TEST(RockMesh, Eota221IsThePlateWithTheFormulasVolumeAndInertiaRatio) {
  // Edges (2c, 2c, c): the 111 block of edge c stretched by (2, 2, 1). Stretching multiplies
  // the volume by 4 and <x^2>, <y^2> by 4: I_zz = (4 + 4) <x^2>_111 m c^2 = 42/85 m c^2,
  // I_xx = I_yy = (4 + 1) <x^2>_111 m c^2 = 21/68 m c^2, I_zz / I_xx = 8/5.
  const double c = 0.465, rho = 2740;
  RockDef d;
  d.shapeClass = "eota_221";
  d.length = 2 * c;
  const TriMesh mesh = makeRockMesh(d);
  const Vec3 extents = mesh.bounds().sizes();
  EXPECT_EQ(extents, Vec3(2 * c, 2 * c, c));
  double unitVolume = 0, meanX2 = 0;
  eotaSweep(unitVolume, meanX2);
  const MassProperties mp = computeMassProperties(mesh, rho);
  const double V = 4 * unitVolume * c * c * c, m = rho * V;
  EXPECT_NEAR(mp.volume, V, 1e-13 * V);
  EXPECT_NEAR(mp.volume, 17.0 / 6 * c * c * c, 1e-13 * V);
  EXPECT_NEAR(mp.inertia(2, 2), 8 * meanX2 * m * c * c, 1e-13 * mp.inertia(2, 2));
  EXPECT_NEAR(mp.inertia(0, 0), 5 * meanX2 * m * c * c, 1e-13 * mp.inertia(0, 0));
  EXPECT_NEAR(mp.inertia(1, 1), mp.inertia(0, 0), 1e-13 * mp.inertia(0, 0));
  EXPECT_NEAR(mp.inertia(2, 2) / mp.inertia(0, 0), 8.0 / 5, 1e-13);
  EXPECT_EQ(facePlanes(mesh), 26u);
}

TEST(RockMesh, EotaBlocksTakeAVolumeOrExtents) {
  // 1 m^3: L = (24/17)^(1/3) = 1.12181 m, the data set's stored 1.122 m.
  const TriMesh a = makeRockMesh(rock("eota_111", 1, 1.0));
  EXPECT_NEAR(computeMassProperties(a, 1).volume, 1.0, 1e-14);
  EXPECT_NEAR(a.bounds().sizes().x(), std::cbrt(24.0 / 17), 1e-14);
  EXPECT_NEAR(a.bounds().sizes().x(), 1.122, 0.5e-3);
  // The field block, 0.93 x 0.93 x 0.47 m: its extents, exactly.
  RockDef d;
  d.shapeClass = "eota_221";
  d.extents = Vec3(0.93, 0.93, 0.47);
  EXPECT_EQ(makeRockMesh(d).bounds().sizes(), d.extents);
}

// --- natural rocks ---------------------------------------------------------------------------

struct ClassRange {
  const char* name;
  double elongationLo, elongationHi, flatnessLo, flatnessHi;  // b/a and c/b
};
// docs/rockfall.md, "Rock shapes": Zingg's classes split at 2/3, drawn down to 1/3.
const ClassRange kNatural[] = {{"compact", 2.0 / 3, 1, 2.0 / 3, 1},
                               {"flat", 2.0 / 3, 1, 1.0 / 3, 2.0 / 3},
                               {"elongated", 1.0 / 3, 2.0 / 3, 2.0 / 3, 1},
                               {"bladed", 1.0 / 3, 2.0 / 3, 1.0 / 3, 2.0 / 3}};

TEST(RockMesh, NaturalRocksAreClosedConvexAndKeepTheirClassRatiosAndVolume) {
  for (const ClassRange& c : kNatural)
    for (std::uint64_t seed = 1; seed <= 25; ++seed) {
      const double V = 0.1 * static_cast<double>(seed);
      TriMesh m = makeRockMesh(rock(c.name, seed, V));
      SCOPED_TRACE(std::string(c.name) + " seed " + std::to_string(seed));
      // Before the closedness check, which would turn an inward mesh outward.
      EXPECT_NEAR(computeMassProperties(m, 1).volume, V, 1e-13 * V);
      EXPECT_NO_THROW(validateClosedMesh(m, c.name));
      EXPECT_LE(worstConvexity(m), 1e-13);
      // Extents along x >= y >= z, ratios in the class's half-open ranges, up to the
      // round-off of one stretch (1e-15 relative).
      const Vec3 e = m.bounds().sizes();
      EXPECT_GE(e.x(), e.y());
      EXPECT_GE(e.y(), e.z());
      const double elongation = e.y() / e.x(), flatness = e.z() / e.y();
      EXPECT_GE(elongation, c.elongationLo - 1e-14);
      EXPECT_LT(elongation, c.elongationHi + 1e-14);
      EXPECT_GE(flatness, c.flatnessLo - 1e-14);
      EXPECT_LT(flatness, c.flatnessHi + 1e-14);
      EXPECT_EQ(rockExtentsProblem(c.name, e), "")
          << "a generated rock outside its own class, unless on a boundary by rounding";
    }
}

TEST(RockMesh, NaturalRocksTakeExtentsOrALongestLength) {
  RockDef d;
  d.shapeClass = "flat";
  d.seed = 4;
  d.extents = Vec3(0.5, 0.4, 0.2);
  const Vec3 e = makeRockMesh(d).bounds().sizes();
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(e[k], d.extents[k], 2e-16 * 0.5) << k;
  d.extents = Vec3::Zero();
  d.length = 2.0;
  const Vec3 l = makeRockMesh(d).bounds().sizes();
  EXPECT_NEAR(l.x(), 2.0, 4e-16);
  EXPECT_EQ(rockExtentsProblem("flat", l), "");
}

TEST(RockMesh, SameSeedSameBytesOtherSeedOtherRock) {
  for (const ClassRange& c : kNatural) {
    const TriMesh a = makeRockMesh(rock(c.name, 7, 0.3)), b = makeRockMesh(rock(c.name, 7, 0.3));
    ASSERT_EQ(a.vertices.size(), b.vertices.size());
    EXPECT_EQ(std::memcmp(a.vertices.data(), b.vertices.data(), a.vertices.size() * sizeof(Vec3)),
              0);
    EXPECT_EQ(a.triangles, b.triangles);
    std::set<std::uint64_t> hashes;
    for (std::uint64_t seed = 0; seed < 20; ++seed)
      hashes.insert(meshHash(makeRockMesh(rock(c.name, seed, 0.3))));
    EXPECT_EQ(hashes.size(), 20u) << c.name << ": two seeds gave the same rock";
  }
  // Pinned: the generator uses integer and IEEE basic arithmetic and square roots only, so this
  // rock is these bits on every machine. A change here changes every scene's rocks (and their
  // checksums): update the value only for an intended change of the construction.
  EXPECT_EQ(meshHash(makeRockMesh(rock("compact", 1, 1.0))), 18095354404291921575u);
}

TEST(RockMesh, ExtentsOutsideANaturalClassAreNamedWithTheirOwnClass) {
  EXPECT_EQ(rockExtentsProblem("compact", Vec3(1, 0.9, 0.8)), "");
  EXPECT_EQ(rockExtentsProblem("flat", Vec3(0.3, 1, 0.9)), "");  // any axis order
  EXPECT_EQ(rockExtentsProblem("eota_221", Vec3(1, 1, 1)), "");  // EOTA blocks stretch
  const std::string p = rockExtentsProblem("flat", Vec3(1, 1, 1));
  EXPECT_NE(p.find("'compact'"), std::string::npos) << p;
  EXPECT_NE(p.find("c/b < 2/3"), std::string::npos) << p;
  EXPECT_NE(rockExtentsProblem("elongated", Vec3(1, 0.9, 0.3)).find("'flat'"), std::string::npos);
  EXPECT_NE(rockExtentsProblem("compact", Vec3(1, 0.5, 0.2)).find("'bladed'"), std::string::npos);
}

TEST(RockMesh, PortableCubeRootIsWithinOneUlp) {
  // Against the C library's long double root, 11 or more bits finer than a double's (std::cbrt
  // itself may be an ulp off).
  Prng rng(3);
  for (int k = 0; k < 5000; ++k) {
    const double x = std::ldexp(rng.uniform(0.5, 1.0), static_cast<int>(rng.uniform(-60, 60)));
    const long double want = std::cbrt(static_cast<long double>(x));
    const double near = static_cast<double>(want);
    const long double ulp = std::nextafter(near, 2 * near) - near;
    EXPECT_LE(std::abs(portableCubeRoot(x) - want), ulp) << x;
  }
  EXPECT_EQ(portableCubeRoot(27.0), 3.0);
  EXPECT_EQ(portableCubeRoot(0.125), 0.5);
}

// --- the convex hull ---------------------------------------------------------------------------

TEST(ConvexHull, KeepsTheCornersDropsInnerPointsAndWindsOutward) {
  std::vector<Vec3> points;
  Prng rng(5);
  for (int k = 0; k < 30; ++k)  // inside the unit cube
    points.emplace_back(rng.uniform(0.1, 0.9), rng.uniform(0.1, 0.9), rng.uniform(0.1, 0.9));
  for (int i = 0; i < 8; ++i) points.emplace_back(i & 1, (i >> 1) & 1, (i >> 2) & 1);
  points.push_back(points.back());  // a repeated corner
  TriMesh hull = convexHull(points);
  EXPECT_EQ(hull.vertices.size(), 8u);
  EXPECT_EQ(hull.triangles.size(), 12u);
  for (const Vec3& v : hull.vertices)
    EXPECT_TRUE(v.cwiseAbs() == v && (v.array() == 0 || v.array() == 1).all()) << v.transpose();
  EXPECT_GT(computeMassProperties(hull, 1).volume, 0);  // outward: positive signed volume
  EXPECT_NEAR(computeMassProperties(hull, 1).volume, 1.0, 1e-15);
  EXPECT_NO_THROW(validateClosedMesh(hull, "hull"));
}

TEST(ConvexHull, SplitsFacesOfManyPointsFromTheirSmallestVertex) {
  // CGAL splits a four-sided face along either diagonal, differently from run to run (its
  // bookkeeping is ordered by addresses); the hull re-splits each planar face as a fan from its
  // smallest vertex index, so the mesh is a function of the points alone. The cube's and the
  // EOTA block's faces: every triangle holds its face's smallest vertex.
  std::vector<Vec3> cube;
  for (int i = 0; i < 8; ++i) cube.emplace_back(i & 1, (i >> 1) & 1, (i >> 2) & 1);
  RockDef eota;
  eota.shapeClass = "eota_111";
  eota.length = 1;
  for (const TriMesh& m : {convexHull(cube), makeRockMesh(eota)}) {
    std::map<std::array<long long, 4>, std::uint32_t> smallest;  // per face plane
    std::vector<std::array<long long, 4>> planeOf;
    for (const auto& t : m.triangles) {
      const Vec3 a = m.vertices[t[0]], b = m.vertices[t[1]], c = m.vertices[t[2]];
      const Vec3 n = (b - a).cross(c - a).normalized();
      const auto r = [](double x) { return std::llround(x * 1e9); };
      const std::array<long long, 4> plane{r(n.x()), r(n.y()), r(n.z()), r(n.dot(a))};
      planeOf.push_back(plane);
      const std::uint32_t least = std::min({t[0], t[1], t[2]});
      const auto [it, added] = smallest.emplace(plane, least);
      it->second = std::min(it->second, least);
    }
    for (std::size_t k = 0; k < m.triangles.size(); ++k) {
      const auto& t = m.triangles[k];
      const std::uint32_t least = smallest.at(planeOf[k]);
      EXPECT_TRUE(t[0] == least || t[1] == least || t[2] == least)
          << "triangle " << k << " misses its face's vertex " << least;
    }
  }
}

}  // namespace
}  // namespace vf

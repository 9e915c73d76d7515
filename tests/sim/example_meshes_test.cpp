// The meshes of the paper's examples 3-6 (scenes/meshes/, written by make_meshes.py) and the
// cliff grid of example 6 (scenes/terrain/cliff.asc), read the way a scene reads them: each
// mesh is closed and outward, has the paper's vertex and triangle counts and masses (section 5,
// README: Reference), and has the shape the example needs (the cross and the barrel
// non-convex, the rock convex but irregular); the grid has the paper's 9.5 m relief and a
// steep face. Convexity oracles here are brute force over vertex triples, independent of sim/.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "sim/geometry/mass_properties.h"
#include "sim/geometry/mesh_checks.h"
#include "sim/geometry/mesh_import.h"
#include "sim/geometry/mesh_query.h"

namespace vf {
namespace {

constexpr double kWood = 800;  // kg/m^3, examples 1-5
// Relative tolerance on volumes and masses of meshes whose dimensions are exact decimals: assimp
// reads coordinates as float, so each edge length carries a relative error of up to
// 2^-24 = 6e-8 and a volume (a product of three lengths) up to about 3 * 2^-24 = 1.8e-7.
// 1e-6 covers that with margin while still telling 670 kg from any rounded alternative
// (1 mm on the 0.67 m edge would change the mass by 1.5e-3 relative).
constexpr double kFloatRel = 1e-6;

std::string scenePath(const std::string& relative) {
  return std::string(VOXFALL_SOURCE_DIR) + "/scenes/" + relative;
}

// Imports and validates a mesh; also fails if validation had to flip it (the file must already
// be counter-clockwise seen from outside).
TriMesh load(const std::string& name) {
  const std::string path = scenePath("meshes/" + name + ".obj");
  TriMesh mesh = importMesh(path);
  const auto before = mesh.triangles;
  validateClosedMesh(mesh, path);
  EXPECT_EQ(mesh.triangles, before) << name << ": triangles were inward and got flipped";
  return mesh;
}

// True if p lies in the convex hull of the mesh's vertices: on the inner side of every plane
// through three vertices that has all vertices on one side (these supporting planes include
// every hull facet, so passing them all means p is in the hull). Brute force, O(n^4).
bool insideConvexHull(const TriMesh& m, const Vec3& p) {
  const auto& v = m.vertices;
  const double eps = 1e-9;
  for (std::size_t i = 0; i < v.size(); ++i)
    for (std::size_t j = i + 1; j < v.size(); ++j)
      for (std::size_t k = j + 1; k < v.size(); ++k) {
        Vec3 n = (v[j] - v[i]).cross(v[k] - v[i]);
        if (n.norm() < 1e-12) continue;  // collinear triple: no plane
        n.normalize();
        double lo = 0, hi = 0;
        for (const Vec3& q : v)
          lo = std::min(lo, n.dot(q - v[i])), hi = std::max(hi, n.dot(q - v[i]));
        const double s = n.dot(p - v[i]);
        if (hi <= eps && s > eps) return false;    // all vertices behind, p in front
        if (lo >= -eps && s < -eps) return false;  // all vertices in front, p behind
      }
  return true;
}

TEST(ExampleMeshes, HighPolyBlockHasThePapersCountsAndMass) {
  // Example 3: 192 triangles, 98 vertices, 670 kg at 800 kg/m^3.
  const TriMesh m = load("highpoly_block");
  EXPECT_EQ(m.vertices.size(), 98u);
  EXPECT_EQ(m.triangles.size(), 192u);
  // The edges, 1.25 x 1.0 x 0.67 m, are whole millimetres whose product is exactly
  // 670 / 800 = 0.8375 m^3, so no dimension is rounded: only the importer's float coordinates
  // (kFloatRel) separate the computed mass from 670 kg.
  const MassProperties mp = computeMassProperties(m, kWood);
  EXPECT_NEAR(mp.volume, 0.8375, 0.8375 * kFloatRel);
  EXPECT_NEAR(mp.mass, 670.0, 670.0 * kFloatRel);
  const Vec3 size = m.bounds().sizes();
  EXPECT_NEAR(size.x(), 1.25, 1e-6);
  EXPECT_NEAR(size.y(), 1.0, 1e-6);
  EXPECT_NEAR(size.z(), 0.67, 1e-6);
}

TEST(ExampleMeshes, StackBlockHasThePapersCountsAndMass) {
  // Example 4: 24 triangles, 44 kg at 800 kg/m^3. 0.55 x 0.4 x 0.25 m is exactly 0.055 m^3,
  // so again only the importer's float coordinates (kFloatRel) separate it from 44 kg.
  const TriMesh m = load("stack_block");
  EXPECT_EQ(m.vertices.size(), 14u);
  EXPECT_EQ(m.triangles.size(), 24u);
  const MassProperties mp = computeMassProperties(m, kWood);
  EXPECT_NEAR(mp.volume, 0.055, 0.055 * kFloatRel);
  EXPECT_NEAR(mp.mass, 44.0, 44.0 * kFloatRel);
}

TEST(ExampleMeshes, CrossHasThePapersCountsAndIsNonConvex) {
  // Example 5: 60 triangles, 32 vertices, non-convex.
  const TriMesh m = load("cross");
  EXPECT_EQ(m.vertices.size(), 32u);
  EXPECT_EQ(m.triangles.size(), 60u);
  const MassProperties mp = computeMassProperties(m, kWood);
  // Outline area 0.188 m^2, 0.15 m thick; symmetric about the origin.
  EXPECT_NEAR(mp.volume, 0.188 * 0.15, 0.188 * 0.15 * kFloatRel);
  EXPECT_NEAR(mp.centerOfMass.norm(), 0.0, 1e-9);
  // The centre and an arm are solid; the point between the +x and +y arms (both arms span
  // |coordinate| <= 0.1 across, so x = y = 0.15 is in neither) is not, yet it is in the convex
  // hull: a solid would contain it if it were convex.
  EXPECT_TRUE(pointInsideMesh(m, Vec3(0, 0, 0)));
  EXPECT_TRUE(pointInsideMesh(m, Vec3(0.2, 0.05, 0)));
  const Vec3 gap(0.15, 0.15, 0);
  EXPECT_FALSE(pointInsideMesh(m, gap));
  EXPECT_TRUE(insideConvexHull(m, gap));
  // Sanity of the hull oracle: a point beyond the line joining the arm ends is outside it.
  EXPECT_FALSE(insideConvexHull(m, Vec3(0.2, 0.2, 0)));
}

TEST(ExampleMeshes, RockHasThePapersCountsAndIsConvexAndIrregular) {
  // Example 6: 24 triangles, 14 vertices.
  const TriMesh m = load("rock");
  EXPECT_EQ(m.vertices.size(), 14u);
  EXPECT_EQ(m.triangles.size(), 24u);
  // Convex: every vertex on or behind every face plane.
  for (const auto& t : m.triangles) {
    const Vec3& a = m.vertices[t[0]];
    const Vec3 n = (m.vertices[t[1]] - a).cross(m.vertices[t[2]] - a).normalized();
    for (const Vec3& q : m.vertices) EXPECT_LE(n.dot(q - a), 1e-9);
  }
  // Irregular: edge lengths differ widely (a regular solid has them all equal).
  std::map<std::pair<std::uint32_t, std::uint32_t>, double> edges;
  for (const auto& t : m.triangles)
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t a = t[k], b = t[(k + 1) % 3];
      edges[{std::min(a, b), std::max(a, b)}] = (m.vertices[a] - m.vertices[b]).norm();
    }
  EXPECT_EQ(edges.size(), 36u);  // 3 * 24 / 2
  double lo = INFINITY, hi = 0;
  for (const auto& [e, len] : edges) lo = std::min(lo, len), hi = std::max(hi, len);
  EXPECT_GT(hi, 1.5 * lo);
  // About 0.5 m across.
  const Vec3 size = m.bounds().sizes();
  EXPECT_GT(size.maxCoeff(), 0.4);
  EXPECT_LT(size.maxCoeff(), 0.6);
}

TEST(ExampleMeshes, BarrelIsAClosedCup) {
  // Example 5b: a thick-walled, open-topped cylinder, bottom at z = 0, 1 m high.
  const TriMesh m = load("barrel");
  EXPECT_EQ(m.vertices.size(), 98u);    // 4 rings of 24 segments + 2 disc centres
  EXPECT_EQ(m.triangles.size(), 192u);  // 24 x (2 outer wall + 2 rim + 2 inner wall + 2 discs)
  const auto box = m.bounds();
  EXPECT_EQ(box.min().z(), 0.0);
  EXPECT_EQ(box.max().z(), 1.0);
  // The axis at mid-height is in the cavity: outside the solid, though inside its hull.
  const Vec3 axis(0, 0, 0.5);
  EXPECT_FALSE(pointInsideMesh(m, axis));
  EXPECT_TRUE(insideConvexHull(m, axis));
  EXPECT_TRUE(pointInsideMesh(m, Vec3(0.47, 0, 0.5)));  // in the wall (radii 0.44 .. 0.5)
  EXPECT_TRUE(pointInsideMesh(m, Vec3(0, 0, 0.03)));    // in the bottom (0 .. 0.06)
  EXPECT_FALSE(pointInsideMesh(m, Vec3(0, 0, 0.09)));   // just above the inner floor
  EXPECT_GT(computeMassProperties(m, kWood).volume, 0);
}

TEST(ExampleTerrain, CliffGridIsNinePointFiveMetresHighWithASteepFace) {
  // Parsed here, independently of loadDem: six "key value" header lines, then nrows
  // lines of ncols heights, the first line the northern-most row.
  const std::string path = scenePath("terrain/cliff.asc");
  std::ifstream in(path);
  ASSERT_TRUE(in) << path;
  std::map<std::string, double> header;
  std::string line;
  for (int k = 0; k < 6 && std::getline(in, line); ++k) {
    std::istringstream s(line);
    std::string key;
    double value;
    ASSERT_TRUE(s >> key >> value) << line;
    header[key] = value;
  }
  for (const char* key : {"ncols", "nrows", "xllcorner", "yllcorner", "cellsize", "NODATA_value"})
    ASSERT_EQ(header.count(key), 1u) << key;
  const int ncols = static_cast<int>(header["ncols"]), nrows = static_cast<int>(header["nrows"]);
  const double cell = header["cellsize"];
  ASSERT_GE(ncols, 2);
  ASSERT_GE(nrows, 2);
  ASSERT_GT(cell, 0);
  std::vector<std::vector<double>> z;  // z[row][col], row 0 north
  while (std::getline(in, line)) {
    if (line.empty()) continue;
    std::istringstream s(line);
    std::vector<double> row;
    for (double v; s >> v;) row.push_back(v);
    ASSERT_TRUE(s.eof()) << "not a number in row " << z.size();
    EXPECT_EQ(static_cast<int>(row.size()), ncols) << "row " << z.size();
    z.push_back(row);
  }
  ASSERT_EQ(static_cast<int>(z.size()), nrows);
  double lo = INFINITY, hi = -INFINITY, steepest = 0;
  for (int r = 0; r < nrows; ++r)
    for (int c = 0; c < ncols; ++c) {
      EXPECT_NE(z[r][c], header["NODATA_value"]);
      lo = std::min(lo, z[r][c]), hi = std::max(hi, z[r][c]);
      if (c + 1 < ncols) steepest = std::max(steepest, std::abs(z[r][c + 1] - z[r][c]));
      if (r + 1 < nrows) steepest = std::max(steepest, std::abs(z[r + 1][c] - z[r][c]));
    }
  EXPECT_NEAR(hi - lo, 9.5, 1e-9);
  const double degrees = std::atan(steepest / cell) * 180 / M_PI;
  EXPECT_GE(degrees, 55);
  EXPECT_LE(degrees, 80);
  // The slope descends along +x: plateau in the west column, the valley floor (the lowest
  // ground) further east, then the counter-slope rising towards the east edge.
  for (int r = 0; r < nrows; ++r) {
    EXPECT_EQ(z[r].front(), hi) << "row " << r;
    const auto low = std::find(z[r].begin(), z[r].end(), lo);
    ASSERT_NE(low, z[r].end()) << "row " << r;
    EXPECT_GT(std::distance(z[r].begin(), low), ncols / 3) << "row " << r << ": past the cliff";
    EXPECT_GT(z[r].back(), lo) << "row " << r << ": the counter-slope rises to the east edge";
  }
}

}  // namespace
}  // namespace vf

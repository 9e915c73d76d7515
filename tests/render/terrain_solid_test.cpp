// A terrain drawn as a solid (render/terrain_solid.h). Oracles: the surface with its sides and
// base encloses the volume between the triangulated surface and the base, computed here cell by
// cell (a triangle's prism down to a plane holds its area times its mean height above it); the
// divergence theorem gives the same number from the triangles only if they close the solid and
// all face outwards. And every edge of the closed surface is shared by triangles from both sides
// (counted by position: the walls have vertices of their own).
#include "render/terrain_solid.h"

#include <gtest/gtest.h>

#include <cmath>
#include <map>

namespace vf {
namespace {

// A 7 x 6 grid of 2 m cells on a tilted, bumpy surface, with a NODATA hole and a missing corner.
Heightfield bumpyWithHoles() {
  Heightfield h;
  h.nx = 7;
  h.ny = 6;
  h.cell = 2;
  h.x0 = 10;
  h.y0 = -4;
  for (int j = 0; j < h.ny; ++j)
    for (int i = 0; i < h.nx; ++i) h.z.push_back(5 + 0.3 * i - 0.2 * j + 0.5 * std::sin(i * j));
  h.z[3 * 7 + 3] = NAN;  // a hole in the middle
  h.z[0] = NAN;          // the south-west corner
  h.zMin = INFINITY, h.zMax = -INFINITY;
  for (const double z : h.z)
    if (!std::isnan(z)) h.zMin = std::min(h.zMin, z), h.zMax = std::max(h.zMax, z);
  return h;
}

// Signed volume enclosed by the triangles (divergence theorem: sum of p0 . (p1 x p2) / 6).
double enclosed(const TriMesh& m) {
  double v = 0;
  for (const auto& t : m.triangles)
    v += m.vertices[t[0]].dot(m.vertices[t[1]].cross(m.vertices[t[2]])) / 6;
  return v;
}

TEST(TerrainSolid, SurfaceSidesAndBaseCloseTheSolidFacingOutwards) {
  const Heightfield h = bumpyWithHoles();
  const double base = terrainBase(h, std::nullopt);
  EXPECT_DOUBLE_EQ(base, h.zMin - std::max(h.cell, 0.05 * (h.zMax - h.zMin)));
  const TriMesh surface = h.toMesh(), sides = terrainSides(h, base);
  double expected = 0;  // prisms of the cells' triangles down to the base
  Vec3 tri[2][3];
  for (int j = 0; j + 1 < h.ny; ++j)
    for (int i = 0; i + 1 < h.nx; ++i) {
      if (!h.hasCell(i, j)) continue;
      h.cellTriangles(i, j, tri);
      for (const auto& t : tri)
        expected += h.cell * h.cell / 2 * ((t[0].z() + t[1].z() + t[2].z()) / 3 - base);
    }
  EXPECT_NEAR(enclosed(surface) + enclosed(sides), expected, 1e-9 * expected);
  // Closed: each edge, by its two end positions, is walked once in each direction.
  std::map<std::pair<std::array<double, 3>, std::array<double, 3>>, int> edges;
  auto key = [](const Vec3& p) { return std::array<double, 3>{p.x(), p.y(), p.z()}; };
  for (const TriMesh* m : {&surface, &sides})
    for (const auto& t : m->triangles)
      for (int k = 0; k < 3; ++k) {
        const Vec3 &a = m->vertices[t[k]], &b = m->vertices[t[(k + 1) % 3]];
        ++edges[{key(a), key(b)}];
      }
  // The base's runs meet their neighbours' at T-junctions; only edges off the base must pair.
  int unpaired = 0;
  for (const auto& [edge, count] : edges) {
    if (edge.first[2] == base && edge.second[2] == base) continue;
    const auto back = edges.find({edge.second, edge.first});
    if (count != 1 || back == edges.end() || back->second != 1) ++unpaired;
  }
  EXPECT_EQ(unpaired, 0);
}

TEST(TerrainSolid, BaseStandsOnAFloorBelowTheTerrainAndIgnoresOneCuttingIt) {
  const Heightfield h = bumpyWithHoles();
  const double own = terrainBase(h, std::nullopt);
  EXPECT_LT(own, h.zMin);
  EXPECT_EQ(terrainBase(h, own - 3), own - 3);   // far below: stands on it
  EXPECT_EQ(terrainBase(h, h.zMin), h.zMin);     // at the lowest sample (a valley floor)
  EXPECT_EQ(terrainBase(h, h.zMin + 0.1), own);  // a floor cutting the terrain hides the rest
  // Standing on a floor the solid is open below: walls and no base face.
  const TriMesh open = terrainSides(h, h.zMin, false);
  EXPECT_GT(open.triangles.size(), 0u);
  for (const auto& t : open.triangles) {
    EXPECT_FALSE(open.vertices[t[0]].z() == h.zMin && open.vertices[t[1]].z() == h.zMin &&
                 open.vertices[t[2]].z() == h.zMin)
        << "a face at the base";
  }
}

}  // namespace
}  // namespace vf

// Mesh repair with CGAL's polygon mesh processing (one of the two files in voxfall that include
// CGAL, with convex_hull.cpp; they are built as their own small library so that CGAL's compile
// options, -frounding-math among them, never reach the simulation's code).
//
// Order of the steps, each one what CGAL documents for its input:
//   1. polygon soup: duplicate triangles (same three vertices, either winding) are merged and
//      triangles that repeat a vertex dropped (repair_polygon_soup);
//   2. orientation: triangles are turned so that neighbours wind the same way, and vertices
//      where the surface pinches are split (orient_polygon_soup);
//   3. the soup becomes a halfedge mesh; zero-area triangles are removed by collapsing or
//      flipping their edges (remove_degenerate_faces, exact predicates); coincident boundary
//      edges are stitched;
//   4. each remaining boundary loop (a hole) of at most RepairLimits::maxHoleEdges edges is
//      triangulated with minimal area (triangulate_hole, no new vertices); a patch larger than
//      RepairLimits::maxHoleAreaFraction of the surface is refused;
//   5. a closed mesh facing inwards is turned inside out.
// Why these bounds: a patch replaces missing surface by the smallest one spanning the hole; the
// volume it adds or removes is at most the patch area times the hole's depth, so small patches
// change mass properties little, while a large one would invent a shape.
#include "sim/geometry/mesh_repair.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/border.h>
#include <CGAL/Polygon_mesh_processing/measure.h>
#include <CGAL/Polygon_mesh_processing/orient_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/orientation.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Polygon_mesh_processing/repair_degeneracies.h>
#include <CGAL/Polygon_mesh_processing/repair_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/shape_predicates.h>
#include <CGAL/Polygon_mesh_processing/stitch_borders.h>
#include <CGAL/Polygon_mesh_processing/triangulate_hole.h>
#include <CGAL/Surface_mesh.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <vector>

#include "sim/core/error.h"

namespace vf {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using Mesh = CGAL::Surface_mesh<Point>;
namespace PMP = CGAL::Polygon_mesh_processing;

std::string plural(std::size_t n, const std::string& word) {
  return std::to_string(n) + " " + word + (n == 1 ? "" : "s");
}

std::string percent(double fraction) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.2g %%", 100 * fraction);
  return buf;
}

Vec3 toVec(const Point& p) { return Vec3(p.x(), p.y(), p.z()); }

// Unnormalised normal of a soup triangle (zero for a degenerate one).
Vec3 soupNormal(const std::vector<Point>& points, const std::vector<std::size_t>& t) {
  const Vec3 a = toVec(points[t[0]]), b = toVec(points[t[1]]), c = toVec(points[t[2]]);
  return (b - a).cross(c - a);
}

// Triangles whose three vertices (in any order) already appeared earlier in the list.
std::size_t countDuplicates(const TriMesh& mesh) {
  std::vector<std::array<std::uint32_t, 3>> keys = mesh.triangles;
  for (auto& k : keys) std::sort(k.begin(), k.end());
  std::sort(keys.begin(), keys.end());
  return static_cast<std::size_t>(keys.end() - std::unique(keys.begin(), keys.end()));
}

std::size_t loopLength(const Mesh& mesh, Mesh::Halfedge_index h) {
  std::size_t n = 0;
  Mesh::Halfedge_index e = h;
  do {
    ++n;
    e = mesh.next(e);
  } while (e != h);
  return n;
}

// Input checks before CGAL sees the mesh: finite coordinates, indices within the vertices.
void checkInput(const TriMesh& input, const std::string& where) {
  for (std::size_t i = 0; i < input.vertices.size(); ++i)
    if (!input.vertices[i].allFinite())
      throw InputError(where, "vertex " + std::to_string(i) + " has a non-finite coordinate");
  for (const auto& t : input.triangles)
    for (std::uint32_t v : t)
      if (v >= input.vertices.size())
        throw InputError(where, "a triangle refers to vertex " + std::to_string(v) +
                                    " but the mesh has only " +
                                    plural(input.vertices.size(), "vertex"));
}

struct Soup {
  std::vector<Point> points;
  std::vector<std::vector<std::size_t>> polygons;
};

// Step 1: the soup, duplicates merged and triangles that repeat a vertex dropped.
Soup repairedSoup(const TriMesh& input, RepairReport& report) {
  Soup soup;
  soup.points.reserve(input.vertices.size());
  for (const Vec3& v : input.vertices) soup.points.emplace_back(v.x(), v.y(), v.z());
  soup.polygons.reserve(input.triangles.size());
  for (const auto& t : input.triangles) soup.polygons.push_back({t[0], t[1], t[2]});
  report.duplicateTriangles = countDuplicates(input);
  for (const auto& t : input.triangles)  // dropped by the soup repair; counted as degenerate
    if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) ++report.degenerateTriangles;
  PMP::repair_polygon_soup(soup.points, soup.polygons);
  return soup;
}

// Step 2: consistent winding; throws when the triangles do not form a surface.
void orientSoup(Soup& soup, const std::string& where, RepairReport& report) {
  std::vector<Vec3> before;
  before.reserve(soup.polygons.size());
  for (const auto& p : soup.polygons) before.push_back(soupNormal(soup.points, p));
  PMP::orient_polygon_soup(soup.points, soup.polygons);
  for (std::size_t i = 0; i < soup.polygons.size() && i < before.size(); ++i)
    if (soupNormal(soup.points, soup.polygons[i]).dot(before[i]) < 0) ++report.reorientedTriangles;
  if (!PMP::is_polygon_soup_a_polygon_mesh(soup.polygons))
    throw InputError(where,
                     "mesh could not be repaired: its triangles do not form a surface "
                     "even after reorienting them (edges shared by more than two "
                     "triangles); separate the touching parts in a mesh editor");
}

// Step 3: the halfedge mesh, degenerate faces removed, coincident boundary edges stitched.
Mesh stitchedMesh(const Soup& soup, RepairReport& report) {
  Mesh mesh;
  PMP::polygon_soup_to_polygon_mesh(soup.points, soup.polygons, mesh);
  std::size_t zeroArea = 0;
  for (Mesh::Face_index f : mesh.faces())
    if (PMP::is_degenerate_triangle_face(f, mesh)) ++zeroArea;
  if (zeroArea > 0) PMP::remove_degenerate_faces(mesh);
  report.degenerateTriangles += zeroArea;
  PMP::stitch_borders(mesh);
  return mesh;
}

// Step 4: each hole triangulated within the limits; throws for one beyond them or a mesh still
// open after.
void fillHoles(Mesh& mesh, const std::string& where, RepairReport& report,
               const RepairLimits& limits) {
  std::vector<Mesh::Halfedge_index> holes;
  PMP::extract_boundary_cycles(mesh, std::back_inserter(holes));
  std::vector<std::pair<std::size_t, double>> patches;  // edges, area
  for (Mesh::Halfedge_index h : holes) {
    const std::size_t edges = loopLength(mesh, h);
    if (edges > limits.maxHoleEdges)
      throw InputError(where, "mesh has a hole of " + std::to_string(edges) +
                                  " boundary edges, more than the " +
                                  std::to_string(limits.maxHoleEdges) +
                                  " that repair fills: close it in a mesh editor");
    std::vector<Mesh::Face_index> patch;
    PMP::triangulate_hole(mesh, h, std::back_inserter(patch));
    if (patch.empty())
      throw InputError(where, "mesh has a hole of " + std::to_string(edges) +
                                  " boundary edges that could not be triangulated: close it in "
                                  "a mesh editor");
    double area = 0;
    for (Mesh::Face_index f : patch) area += PMP::face_area(f, mesh);
    patches.emplace_back(edges, area);
    report.patchTriangles += patch.size();
    report.patchArea += area;
  }
  report.holesFilled = patches.size();
  const double surface = PMP::area(mesh);
  for (const auto& [edges, area] : patches) {
    const double fraction = surface > 0 ? area / surface : 1.0;
    report.largestPatchFraction = std::max(report.largestPatchFraction, fraction);
    if (fraction > limits.maxHoleAreaFraction)
      throw InputError(where, "mesh has a hole of " + std::to_string(edges) +
                                  " boundary edges whose patch would cover " + percent(fraction) +
                                  " of the surface, more than the " +
                                  percent(limits.maxHoleAreaFraction) +
                                  " that repair fills: close it in a mesh editor");
  }
  if (!CGAL::is_closed(mesh))
    throw InputError(where, "mesh is still not closed after repair; close it in a mesh editor");
}

// The halfedge mesh back as voxfall's triangle list, garbage collected first so that vertex
// indices are dense.
TriMesh toTriMesh(Mesh& mesh) {
  mesh.collect_garbage();
  TriMesh out;
  out.vertices.reserve(mesh.number_of_vertices());
  for (Mesh::Vertex_index v : mesh.vertices()) out.vertices.push_back(toVec(mesh.point(v)));
  out.triangles.reserve(mesh.number_of_faces());
  for (Mesh::Face_index f : mesh.faces()) {
    std::array<std::uint32_t, 3> t{};
    int k = 0;
    for (Mesh::Vertex_index v : CGAL::vertices_around_face(mesh.halfedge(f), mesh))
      if (k < 3) t[k++] = static_cast<std::uint32_t>(v.idx());
    if (k == 3) out.triangles.push_back(t);
  }
  return out;
}

}  // namespace

std::string RepairReport::summary() const {
  std::vector<std::string> parts;
  if (holesFilled > 0)
    parts.push_back("filled " + plural(holesFilled, "hole") + " with " +
                    plural(patchTriangles, "triangle") + " (largest patch " +
                    percent(largestPatchFraction) + " of the surface)");
  if (duplicateTriangles > 0)
    parts.push_back("removed " + plural(duplicateTriangles, "duplicate triangle"));
  if (degenerateTriangles > 0)
    parts.push_back("removed " + plural(degenerateTriangles, "degenerate triangle"));
  if (reorientedTriangles > 0)
    parts.push_back("turned " + plural(reorientedTriangles, "triangle") +
                    " to wind like their neighbours");
  if (flippedInsideOut) parts.push_back("turned the mesh outward");
  if (parts.empty()) return "nothing to repair";
  std::string s;
  for (std::size_t i = 0; i < parts.size(); ++i) s += (i == 0 ? "" : ", ") + parts[i];
  return s;
}

TriMesh repairMesh(const TriMesh& input, const std::string& where, RepairReport& report,
                   const RepairLimits& limits) {
  report = RepairReport{};
  checkInput(input, where);
  Soup soup = repairedSoup(input, report);
  orientSoup(soup, where, report);
  Mesh mesh = stitchedMesh(soup, report);
  fillHoles(mesh, where, report, limits);
  // Step 5: outward.
  if (!PMP::is_outward_oriented(mesh)) {
    PMP::reverse_face_orientations(mesh);
    report.flippedInsideOut = true;
  }
  return toTriMesh(mesh);
}

}  // namespace vf

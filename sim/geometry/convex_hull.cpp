// Convex hulls through CGAL (quickhull with exact predicates). Exact predicates make the hull's
// combinatorics a function of the input doubles alone, the same on every machine; the output
// coordinates are the input's own, so nothing CGAL computes in floating point reaches a mesh.
#include "sim/geometry/convex_hull.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/convex_hull_3.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <map>
#include <set>
#include <tuple>
#include <utility>

#include "sim/core/error.h"

namespace vf {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;

// The hull's planar faces, each as triangles of vertex indices: neighbouring triangles whose
// four points lie on one plane (CGAL's exact predicate) belong to one face.
std::vector<std::vector<std::array<std::uint32_t, 3>>> planarFaces(
    const std::vector<Point>& p, const std::vector<std::array<std::uint32_t, 3>>& triangles) {
  std::vector<std::size_t> parent(triangles.size());
  for (std::size_t i = 0; i < parent.size(); ++i) parent[i] = i;
  const auto root = [&](std::size_t i) {
    while (parent[i] != i) i = parent[i] = parent[parent[i]];
    return i;
  };
  std::map<std::pair<std::uint32_t, std::uint32_t>, std::size_t> edgeOf;  // directed edge
  for (std::size_t i = 0; i < triangles.size(); ++i)
    for (int k = 0; k < 3; ++k) edgeOf[{triangles[i][k], triangles[i][(k + 1) % 3]}] = i;
  for (std::size_t i = 0; i < triangles.size(); ++i)
    for (int k = 0; k < 3; ++k) {
      const auto& t = triangles[i];
      const auto other = edgeOf.find({t[(k + 1) % 3], t[k]});
      VF_ASSERT(other != edgeOf.end());  // a hull is closed
      const auto& u = triangles[other->second];
      std::uint32_t apex = u[0];
      for (std::uint32_t v : u)
        if (v != t[k] && v != t[(k + 1) % 3]) apex = v;
      if (CGAL::coplanar(p[t[0]], p[t[1]], p[t[2]], p[apex])) parent[root(i)] = root(other->second);
    }
  std::map<std::size_t, std::vector<std::array<std::uint32_t, 3>>> faces;
  for (std::size_t i = 0; i < triangles.size(); ++i) faces[root(i)].push_back(triangles[i]);
  std::vector<std::vector<std::array<std::uint32_t, 3>>> out;
  for (auto& [r, f] : faces) out.push_back(std::move(f));
  return out;
}

// A convex planar face as a fan from its smallest vertex, around its boundary (the directed
// edges no other triangle of the face runs back along), winding kept.
void fanFromSmallest(const std::vector<std::array<std::uint32_t, 3>>& face,
                     std::vector<std::array<std::uint32_t, 3>>& out) {
  if (face.size() == 1) {
    out.push_back(face[0]);
    return;
  }
  std::set<std::pair<std::uint32_t, std::uint32_t>> edges;
  for (const auto& t : face)
    for (int k = 0; k < 3; ++k) edges.insert({t[k], t[(k + 1) % 3]});
  std::map<std::uint32_t, std::uint32_t> next;
  for (const auto& [a, b] : edges)
    if (!edges.count({b, a})) next[a] = b;
  std::vector<std::uint32_t> loop{next.begin()->first};  // the smallest boundary vertex
  while (loop.size() <= next.size()) {
    const std::uint32_t v = next.at(loop.back());
    if (v == loop.front()) break;
    loop.push_back(v);
  }
  VF_ASSERT(loop.size() == next.size());  // one boundary loop: the face has no hole
  for (std::size_t i = 1; i + 1 < loop.size(); ++i) out.push_back({loop[0], loop[i], loop[i + 1]});
}

}  // namespace

TriMesh convexHull(const std::vector<Vec3>& points) {
  std::vector<Point> input;
  input.reserve(points.size());
  for (const Vec3& p : points) input.emplace_back(p.x(), p.y(), p.z());
  std::vector<Point> hullPoints;
  std::vector<std::array<std::size_t, 3>> faces;
  CGAL::convex_hull_3(input.begin(), input.end(), hullPoints, faces);
  VF_ASSERT(hullPoints.size() >= 4 && faces.size() >= 4);

  // Back to the caller's points: the first input index holding each hull point's coordinates,
  // and the mesh's vertices in input order, so the mesh does not depend on CGAL's vertex order.
  using Key = std::tuple<double, double, double>;
  std::map<Key, std::size_t> firstIndex;
  for (std::size_t i = 0; i < points.size(); ++i)
    firstIndex.emplace(Key{points[i].x(), points[i].y(), points[i].z()}, i);
  std::map<std::size_t, std::uint32_t> meshIndex;  // input index -> mesh vertex, input order
  std::vector<std::size_t> inputOf(hullPoints.size());
  for (std::size_t h = 0; h < hullPoints.size(); ++h) {
    const Point& p = hullPoints[h];
    const auto it = firstIndex.find(Key{p.x(), p.y(), p.z()});
    VF_ASSERT(it != firstIndex.end());
    inputOf[h] = it->second;
    meshIndex.emplace(it->second, 0);
  }
  TriMesh mesh;
  for (auto& [input, index] : meshIndex) {
    index = static_cast<std::uint32_t>(mesh.vertices.size());
    mesh.vertices.push_back(points[input]);
  }
  std::vector<std::array<std::uint32_t, 3>> triangles;
  for (const auto& f : faces)
    triangles.push_back(
        {meshIndex.at(inputOf[f[0]]), meshIndex.at(inputOf[f[1]]), meshIndex.at(inputOf[f[2]])});
  // CGAL splits a face of more than three points one way or another from run to run (its
  // bookkeeping is ordered by addresses): each such face is split again as a fan from its
  // smallest vertex. Then each triangle starts at its smallest vertex (winding kept) and the
  // list is sorted, so the mesh, and every sum over its triangles, is a function of the points.
  std::vector<Point> meshPoints;
  for (const Vec3& v : mesh.vertices) meshPoints.emplace_back(v.x(), v.y(), v.z());
  for (const auto& face : planarFaces(meshPoints, triangles)) fanFromSmallest(face, mesh.triangles);
  for (auto& t : mesh.triangles)
    std::rotate(t.begin(), std::min_element(t.begin(), t.end()), t.end());
  std::sort(mesh.triangles.begin(), mesh.triangles.end());
  return mesh;
}

}  // namespace vf

// Flat faces: adjacent triangles whose normals agree to 1e-9 (a box face split in two, the
// gridded faces of example 3's block) form one face. The polygon collider still tests every
// triangle and every edge, as the paper's baseline treats the mesh's own polygons; the merged
// faces only give the outline against which a face-face contact is clipped.
#include "sim/shape/convex_polyhedron.h"

#include <algorithm>
#include <map>
#include <numeric>
#include <utility>

#include "sim/core/error.h"

namespace vf {
namespace {

double meshSize(const TriMesh& mesh) { return mesh.bounds().sizes().maxCoeff(); }

Vec3 triangleNormal(const TriMesh& m, const std::array<std::uint32_t, 3>& t) {
  const Vec3& a = m.vertices[t[0]];
  return (m.vertices[t[1]] - a).cross(m.vertices[t[2]] - a).normalized();
}

int findRoot(std::vector<int>& parent, int i) {
  while (parent[i] != i) i = parent[i] = parent[parent[i]];
  return i;
}

}  // namespace

bool isConvexMesh(const TriMesh& mesh) {
  const double tolerance = 1e-7 * meshSize(mesh);
  for (const auto& t : mesh.triangles) {
    const Vec3 n = triangleNormal(mesh, t);
    const double d = n.dot(mesh.vertices[t[0]]);
    for (const Vec3& v : mesh.vertices)
      if (n.dot(v) - d > tolerance) return false;
  }
  return true;
}

ConvexPolyhedron buildConvexPolyhedron(const TriMesh& mesh, const std::string& shapeName,
                                       const std::string& where) {
  if (!isConvexMesh(mesh))
    throw InputError(where, "shape '" + shapeName +
                                "' is not convex: the polygon method handles convex meshes "
                                "only; use collider = \"voxel\"");
  ConvexPolyhedron p;
  p.vertices = mesh.vertices;
  p.triangles = mesh.triangles;
  for (const Vec3& v : p.vertices) p.boundingRadius = std::max(p.boundingRadius, v.norm());
  const int nt = static_cast<int>(mesh.triangles.size());
  for (const auto& t : mesh.triangles) {
    p.triangleNormals.push_back(triangleNormal(mesh, t));
    p.triangleOffsets.push_back(p.triangleNormals.back().dot(mesh.vertices[t[0]]));
  }

  // Edges: each undirected edge once (sorted by its vertex pair: a fixed order), with the
  // triangle on either side. The mesh is closed, so every edge has exactly two.
  std::map<std::pair<std::uint32_t, std::uint32_t>, ConvexPolyhedron::Edge> edges;
  std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> directed;  // u->v: triangle
  for (int i = 0; i < nt; ++i) {
    const auto& t = mesh.triangles[i];
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t u = t[k], v = t[(k + 1) % 3];
      directed[{u, v}] = static_cast<std::uint32_t>(i);
      auto key = std::minmax(u, v);
      auto [it, fresh] = edges.try_emplace({key.first, key.second});
      if (fresh) {
        it->second.v0 = key.first;
        it->second.v1 = key.second;
        it->second.t0 = static_cast<std::uint32_t>(i);
      } else {
        it->second.t1 = static_cast<std::uint32_t>(i);
      }
    }
  }
  for (const auto& [key, e] : edges) p.edges.push_back(e);

  // Flat faces: union the two triangles of every edge whose normals agree.
  std::vector<int> parent(nt);
  std::iota(parent.begin(), parent.end(), 0);
  for (const auto& e : p.edges)
    if (p.triangleNormals[e.t0].dot(p.triangleNormals[e.t1]) > 1 - 1e-9)
      parent[findRoot(parent, static_cast<int>(e.t0))] = findRoot(parent, static_cast<int>(e.t1));
  std::map<int, std::uint32_t> faceOfRoot;
  p.triangleFace.resize(nt);
  for (int i = 0; i < nt; ++i) {
    const int root = findRoot(parent, i);
    auto [it, fresh] = faceOfRoot.try_emplace(root, static_cast<std::uint32_t>(p.faces.size()));
    if (fresh) {
      ConvexPolyhedron::Face f;
      f.normal = p.triangleNormals[root];
      f.offset = p.triangleOffsets[root];
      p.faces.push_back(f);
    }
    p.triangleFace[i] = it->second;
  }
  // Each face's outline: its triangles' directed edges whose twin belongs to another face,
  // chained head to tail (counter-clockwise about the outward normal, as the triangles are).
  std::vector<std::map<std::uint32_t, std::uint32_t>> next(p.faces.size());
  for (const auto& [uv, tri] : directed) {
    const auto twin = directed.find({uv.second, uv.first});
    VF_ASSERT(twin != directed.end());
    if (p.triangleFace[twin->second] != p.triangleFace[tri])
      next[p.triangleFace[tri]][uv.first] = uv.second;
  }
  for (std::size_t f = 0; f < p.faces.size(); ++f) {
    VF_ASSERT(!next[f].empty());
    const std::uint32_t start = next[f].begin()->first;
    std::uint32_t v = start;
    do {
      p.faces[f].loop.push_back(v);
      v = next[f].at(v);
    } while (v != start && p.faces[f].loop.size() <= next[f].size());
  }
  return p;
}

}  // namespace vf

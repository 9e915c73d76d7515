#include "render/smooth_normals.h"

#include <cmath>
#include <cstdint>
#include <numbers>
#include <numeric>

namespace vf {
namespace {

// The unit normal of triangle t (zero when degenerate) and its angle at each corner.
struct Face {
  Vec3 normal = Vec3::Zero();
  std::array<double, 3> angle{};
};

Face face(const TriMesh& mesh, const std::array<std::uint32_t, 3>& t) {
  Face f;
  const Vec3 n =
      (mesh.vertices[t[1]] - mesh.vertices[t[0]]).cross(mesh.vertices[t[2]] - mesh.vertices[t[0]]);
  if (!(n.norm() > 0)) return f;
  f.normal = n.normalized();
  for (int corner = 0; corner < 3; ++corner) {
    const Vec3& p = mesh.vertices[t[corner]];
    const Vec3 a = mesh.vertices[t[(corner + 1) % 3]] - p;
    const Vec3 b = mesh.vertices[t[(corner + 2) % 3]] - p;
    f.angle[static_cast<std::size_t>(corner)] = std::atan2(a.cross(b).norm(), a.dot(b));
  }
  return f;
}

// Union-find over the triangles around one vertex (a handful): path halving.
std::size_t root(std::vector<std::size_t>& parent, std::size_t i) {
  while (parent[i] != i) i = parent[i] = parent[parent[i]];
  return i;
}

}  // namespace

std::vector<Vec3> smoothVertexNormals(const TriMesh& mesh) {
  // Each face normal weighted by the face's angle at the vertex: unlike area weights, the
  // result does not depend on how a surface happens to be cut into triangles (a grid cell's
  // diagonal would otherwise tilt the normals towards its side).
  std::vector<Vec3> normals(mesh.vertices.size(), Vec3::Zero());
  for (const auto& t : mesh.triangles) {
    const Face f = face(mesh, t);
    for (int corner = 0; corner < 3; ++corner)
      normals[t[corner]] += f.normal * f.angle[static_cast<std::size_t>(corner)];
  }
  for (Vec3& n : normals) n = n.norm() > 0 ? Vec3(n.normalized()) : Vec3(Vec3::UnitZ());
  return normals;
}

CreasedMesh creasedNormals(const TriMesh& mesh, double creaseDegrees) {
  const std::size_t nv = mesh.vertices.size(), nt = mesh.triangles.size();
  std::vector<Face> faces(nt);
  for (std::size_t t = 0; t < nt; ++t) faces[t] = face(mesh, mesh.triangles[t]);
  // The triangle corners around each vertex, in triangle order (counting sort).
  std::vector<std::size_t> start(nv + 1, 0);
  for (const auto& t : mesh.triangles)
    for (const std::uint32_t v : t) ++start[v + 1];
  std::partial_sum(start.begin(), start.end(), start.begin());
  std::vector<std::size_t> corners(3 * nt), fill(start.begin(), start.end() - 1);
  for (std::size_t t = 0; t < nt; ++t)
    for (std::size_t c = 0; c < 3; ++c) corners[fill[mesh.triangles[t][c]]++] = 3 * t + c;

  // Faces whose normals differ by at most the crease angle: cosine at least this. The slack
  // keeps exactly coplanar faces (cosine 1 up to rounding) together at a crease of 0.
  const double least = std::cos(creaseDegrees * std::numbers::pi / 180) - 1e-12;
  CreasedMesh out;
  out.mesh.triangles = mesh.triangles;
  std::vector<std::size_t> parent;
  std::vector<std::uint32_t> group;
  for (std::size_t v = 0; v < nv; ++v) {
    const std::size_t first = start[v], count = start[v + 1] - first;
    parent.resize(count);
    std::iota(parent.begin(), parent.end(), std::size_t{0});
    for (std::size_t a = 0; a < count; ++a) {
      const std::size_t ta = corners[first + a] / 3, ca = corners[first + a] % 3;
      const Face& fa = faces[ta];
      if (!(fa.normal.norm() > 0)) continue;
      for (std::size_t b = a + 1; b < count; ++b) {
        const std::size_t tb = corners[first + b] / 3, cb = corners[first + b] % 3;
        const Face& fb = faces[tb];
        if (!(fb.normal.norm() > 0) || fa.normal.dot(fb.normal) < least) continue;
        // Neighbours around v: they share an edge through v, i.e. another vertex.
        const auto& A = mesh.triangles[ta];
        const auto& B = mesh.triangles[tb];
        const std::uint32_t a1 = A[(ca + 1) % 3], a2 = A[(ca + 2) % 3];
        const std::uint32_t b1 = B[(cb + 1) % 3], b2 = B[(cb + 2) % 3];
        if (a1 == b1 || a1 == b2 || a2 == b1 || a2 == b2) parent[root(parent, b)] = root(parent, a);
      }
    }
    // One copy of the vertex per group, in the order of the groups' first corners.
    group.assign(count, UINT32_MAX);
    for (std::size_t a = 0; a < count; ++a) {
      const std::size_t r = root(parent, a);
      if (group[r] == UINT32_MAX) {
        group[r] = static_cast<std::uint32_t>(out.mesh.vertices.size());
        out.mesh.vertices.push_back(mesh.vertices[v]);
        out.normals.push_back(Vec3::Zero());
      }
      const std::size_t t = corners[first + a] / 3, c = corners[first + a] % 3;
      out.mesh.triangles[t][c] = group[r];
      out.normals[group[r]] += faces[t].normal * faces[t].angle[c];
    }
  }
  for (Vec3& n : out.normals) n = n.norm() > 0 ? Vec3(n.normalized()) : Vec3(Vec3::UnitZ());
  return out;
}

}  // namespace vf

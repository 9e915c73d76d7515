// Median-split AABB tree, leaves of at most kLeafSize triangles, nearest-point search that
// visits the nearer child first and skips every box farther than the best distance so far.
// Alternatives rejected: a uniform grid (poor on meshes with very uneven triangle sizes such
// as the cross and the barrel), and the hierarchical fast winding number (Barill et al. 2018),
// which approximates far clusters and so would weaken what the diagnostics guarantee.
#include "sim/geometry/mesh_bvh.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <utility>

#include "sim/core/error.h"

namespace vf {
namespace {

constexpr std::uint32_t kLeafSize = 4;

// Squared distance from p to the box [lo, hi] (0 inside).
double boxDistance2(const Vec3& p, const Vec3& lo, const Vec3& hi) {
  return (lo - p).cwiseMax(p - hi).cwiseMax(0.0).squaredNorm();
}

// Interior angle of the triangle at vertex a.
double angleAt(const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 u = b - a, v = c - a;
  return std::atan2(u.cross(v).norm(), u.dot(v));
}

// The normals a nearest-point query signs its distance with: per face, per vertex (angle
// weighted) and per edge of each triangle (the sum of the edge's two face normals).
struct Pseudonormals {
  std::vector<Vec3> face;                 // per triangle, unit
  std::vector<Vec3> vertex;               // per vertex
  std::vector<std::array<Vec3, 3>> edge;  // per triangle, its edges k -> k + 1
};

// Face normals and angle-weighted vertex pseudonormals.
void facePseudonormals(const TriMesh& mesh, Pseudonormals& n) {
  const std::size_t nt = mesh.triangles.size();
  n.face.resize(nt);
  n.vertex.assign(mesh.vertices.size(), Vec3::Zero());
  for (std::size_t t = 0; t < nt; ++t) {
    const auto& tri = mesh.triangles[t];
    const Vec3 &a = mesh.vertices[tri[0]], &b = mesh.vertices[tri[1]], &c = mesh.vertices[tri[2]];
    n.face[t] = (b - a).cross(c - a).normalized();
    n.vertex[tri[0]] += angleAt(a, b, c) * n.face[t];
    n.vertex[tri[1]] += angleAt(b, c, a) * n.face[t];
    n.vertex[tri[2]] += angleAt(c, a, b) * n.face[t];
  }
}

// Edge pseudonormals: the two faces of each undirected edge (manifold: exactly two), found by
// sorting (min, max, triangle) keys: deterministic, no hashing.
void edgePseudonormals(const TriMesh& mesh, Pseudonormals& n) {
  struct EdgeUse {
    std::uint32_t lo, hi, tri;
    bool operator<(const EdgeUse& o) const {
      return std::tie(lo, hi, tri) < std::tie(o.lo, o.hi, o.tri);
    }
  };
  const std::size_t nt = mesh.triangles.size();
  std::vector<EdgeUse> uses;
  uses.reserve(3 * nt);
  for (std::uint32_t t = 0; t < nt; ++t)
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t u = mesh.triangles[t][k], v = mesh.triangles[t][(k + 1) % 3];
      uses.push_back({std::min(u, v), std::max(u, v), t});
    }
  std::sort(uses.begin(), uses.end());
  n.edge.resize(nt);
  for (std::size_t i = 0; i < uses.size();) {
    std::size_t j = i;
    Vec3 sum = Vec3::Zero();
    while (j < uses.size() && uses[j].lo == uses[i].lo && uses[j].hi == uses[i].hi)
      sum += n.face[uses[j++].tri];
    for (std::size_t k = i; k < j; ++k) {
      const auto& tri = mesh.triangles[uses[k].tri];
      for (int e = 0; e < 3; ++e) {
        const std::uint32_t u = tri[e], v = tri[(e + 1) % 3];
        if (std::min(u, v) == uses[k].lo && std::max(u, v) == uses[k].hi)
          n.edge[uses[k].tri][e] = sum;
      }
    }
    i = j;
  }
}

Pseudonormals pseudonormals(const TriMesh& mesh) {
  Pseudonormals n;
  facePseudonormals(mesh, n);
  edgePseudonormals(mesh, n);
  return n;
}

}  // namespace

Vec3 closestPointOnTriangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c,
                            TriangleFeature& feature) {
  // Voronoi regions of the triangle: vertices, then edges, then the face (barycentric).
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return feature = TriangleFeature::kVertex0, a;
  const Vec3 bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return feature = TriangleFeature::kVertex1, b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0)
    return feature = TriangleFeature::kEdge0, a + (d1 / (d1 - d3)) * ab;
  const Vec3 cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return feature = TriangleFeature::kVertex2, c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0)
    return feature = TriangleFeature::kEdge2, a + (d2 / (d2 - d6)) * ac;
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0)
    return feature = TriangleFeature::kEdge1, b + ((d4 - d3) / ((d4 - d3) + (d5 - d6))) * (c - b);
  const double denom = 1 / (va + vb + vc);
  feature = TriangleFeature::kFace;
  return a + ab * (vb * denom) + ac * (vc * denom);
}

MeshBvh::MeshBvh(const TriMesh& mesh) {
  const std::size_t nt = mesh.triangles.size();
  VF_ASSERT(nt > 0);
  const Pseudonormals normals = pseudonormals(mesh);
  const std::vector<Vec3>& faceN = normals.face;
  const std::vector<Vec3>& vertexN = normals.vertex;
  const std::vector<std::array<Vec3, 3>>& edgeN = normals.edge;

  // Median split over triangle centroids along the widest axis of their bounds.
  std::vector<std::uint32_t> order(nt);
  std::iota(order.begin(), order.end(), 0u);
  std::vector<Vec3> centroid(nt);
  for (std::size_t t = 0; t < nt; ++t) {
    const auto& tri = mesh.triangles[t];
    centroid[t] = (mesh.vertices[tri[0]] + mesh.vertices[tri[1]] + mesh.vertices[tri[2]]) / 3;
  }
  nodes_.reserve(2 * (nt / kLeafSize + 1));
  auto build = [&](auto& self, std::uint32_t node, std::uint32_t begin, std::uint32_t end) -> void {
    Eigen::AlignedBox3d box, cbox;
    for (std::uint32_t i = begin; i < end; ++i) {
      for (std::uint32_t v : mesh.triangles[order[i]]) box.extend(mesh.vertices[v]);
      cbox.extend(centroid[order[i]]);
    }
    nodes_[node].lo = box.min();
    nodes_[node].hi = box.max();
    if (end - begin <= kLeafSize) {
      nodes_[node].first = begin;
      nodes_[node].count = end - begin;
      return;
    }
    int axis;
    cbox.sizes().maxCoeff(&axis);
    const std::uint32_t mid = begin + (end - begin) / 2;
    std::nth_element(order.begin() + begin, order.begin() + mid, order.begin() + end,
                     [&](std::uint32_t x, std::uint32_t y) {
                       const double cx = centroid[x][axis], cy = centroid[y][axis];
                       return cx < cy || (cx == cy && x < y);  // total order: deterministic
                     });
    const auto left = static_cast<std::uint32_t>(nodes_.size());
    nodes_.resize(nodes_.size() + 2);
    nodes_[node].first = left;
    nodes_[node].count = 0;
    self(self, left, begin, mid);
    self(self, left + 1, mid, end);
  };
  nodes_.resize(1);
  build(build, 0, 0, static_cast<std::uint32_t>(nt));

  triangles_.resize(nt);
  for (std::size_t i = 0; i < nt; ++i) {
    const std::uint32_t t = order[i];
    Triangle& T = triangles_[i];
    for (int k = 0; k < 3; ++k) {
      T.v[k] = mesh.vertices[mesh.triangles[t][k]];
      T.vertexNormal[k] = vertexN[mesh.triangles[t][k]];
      T.edgeNormal[k] = edgeN[t][k];
    }
    T.faceNormal = faceN[t];
  }
}

MeshBvh::Nearest MeshBvh::nearest(const Vec3& p, double enough) const {
  const double enough2 = enough >= 0 ? enough * enough : -1;
  double best2 = std::numeric_limits<double>::infinity();
  Vec3 bestPoint = Vec3::Zero();
  Vec3 bestNormal = Vec3::Zero();
  std::uint32_t stack[64];
  int top = 0;
  stack[top++] = 0;
  while (top > 0 && best2 > enough2) {
    const Node& n = nodes_[stack[--top]];
    if (boxDistance2(p, n.lo, n.hi) >= best2) continue;
    if (n.count == 0) {
      // Nearer child last, so it is popped first.
      const double dl = boxDistance2(p, nodes_[n.first].lo, nodes_[n.first].hi);
      const double dr = boxDistance2(p, nodes_[n.first + 1].lo, nodes_[n.first + 1].hi);
      const bool leftFirst = dl <= dr;
      stack[top++] = leftFirst ? n.first + 1 : n.first;
      stack[top++] = leftFirst ? n.first : n.first + 1;
      continue;
    }
    for (std::uint32_t i = n.first; i < n.first + n.count; ++i) {
      const Triangle& T = triangles_[i];
      TriangleFeature f;
      const Vec3 q = closestPointOnTriangle(p, T.v[0], T.v[1], T.v[2], f);
      const double d2 = (p - q).squaredNorm();
      if (d2 >= best2) continue;
      best2 = d2;
      bestPoint = q;
      switch (f) {
        case TriangleFeature::kFace:
          bestNormal = T.faceNormal;
          break;
        case TriangleFeature::kEdge0:
          bestNormal = T.edgeNormal[0];
          break;
        case TriangleFeature::kEdge1:
          bestNormal = T.edgeNormal[1];
          break;
        case TriangleFeature::kEdge2:
          bestNormal = T.edgeNormal[2];
          break;
        case TriangleFeature::kVertex0:
          bestNormal = T.vertexNormal[0];
          break;
        case TriangleFeature::kVertex1:
          bestNormal = T.vertexNormal[1];
          break;
        case TriangleFeature::kVertex2:
          bestNormal = T.vertexNormal[2];
          break;
      }
    }
  }
  Nearest r;
  r.distance = std::sqrt(best2);
  r.point = bestPoint;
  r.inside = (p - bestPoint).dot(bestNormal) < 0;
  return r;
}

std::size_t MeshBvh::memoryBytes() const {
  return nodes_.capacity() * sizeof(Node) + triangles_.capacity() * sizeof(Triangle);
}

}  // namespace vf

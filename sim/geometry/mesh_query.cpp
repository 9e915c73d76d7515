// Point queries on a closed mesh for diagnostics (interpenetration, tunnelling). Brute force
// over the triangles: they run on sampled states, not inside the step, so clarity wins.
#include "sim/geometry/mesh_query.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <utility>

#include "sim/geometry/cell_grid.h"

namespace vf {
namespace {

// Signed solid angle of triangle (a, b, c) seen from the origin (Van Oosterom & Strackee):
// tan(omega / 2) = a.(b x c) / (|a||b||c| + (a.b)|c| + (a.c)|b| + (b.c)|a|). atan2 keeps the
// correct branch when the denominator is negative (|omega| > pi).
double solidAngle(const Vec3& a, const Vec3& b, const Vec3& c) {
  const double la = a.norm(), lb = b.norm(), lc = c.norm();
  const double num = a.dot(b.cross(c));
  const double den = la * lb * lc + a.dot(b) * lc + a.dot(c) * lb + b.dot(c) * la;
  return 2 * std::atan2(num, den);
}

double pointSegmentDistance(const Vec3& p, const Vec3& a, const Vec3& b) {
  const Vec3 ab = b - a;
  const double len2 = ab.squaredNorm();
  const double t = len2 > 0 ? std::clamp((p - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
  return (a + t * ab - p).norm();
}

// Exact distance from p to the closed triangle (a, b, c): if the projection of p onto the
// plane falls inside the triangle the distance is the plane distance; otherwise the nearest
// point is on the boundary (the triangle is convex), i.e. on one of the three edges.
double pointTriangleDistance(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 n = (b - a).cross(c - a);
  const double n2 = n.squaredNorm();
  if (n2 > 0) {
    // Barycentric signs of the projection: p inside iff it is on the inner side of all edges.
    const Vec3 pa = a - p, pb = b - p, pc = c - p;
    const double u = n.dot(pb.cross(pc));  // weight of a (times |n|^2)
    const double v = n.dot(pc.cross(pa));  // weight of b
    const double w = n.dot(pa.cross(pb));  // weight of c
    if (u >= 0 && v >= 0 && w >= 0) return std::abs(n.dot(p - a)) / std::sqrt(n2);
  }
  return std::min({pointSegmentDistance(p, a, b), pointSegmentDistance(p, b, c),
                   pointSegmentDistance(p, c, a)});
}

}  // namespace

bool pointInsideMesh(const TriMesh& mesh, const Vec3& p) {
  // Generalised winding number: the solid angles of an outward closed surface sum to 4 pi
  // from inside and 0 from outside; > 2 pi (winding > 1/2) is robust to small cracks.
  double total = 0;
  for (const auto& t : mesh.triangles) {
    total += solidAngle(mesh.vertices[t[0]] - p, mesh.vertices[t[1]] - p, mesh.vertices[t[2]] - p);
  }
  return total > 2 * std::numbers::pi;
}

double distanceToMesh(const TriMesh& mesh, const Vec3& p) {
  double best = std::numeric_limits<double>::infinity();
  for (const auto& t : mesh.triangles) {
    best = std::min(best, pointTriangleDistance(p, mesh.vertices[t[0]], mesh.vertices[t[1]],
                                                mesh.vertices[t[2]]));
  }
  return best;
}

std::vector<Vec3> surfaceSamples(const TriMesh& mesh) {
  // Each undirected edge once, in sorted order (deterministic, no hashing).
  std::vector<std::pair<std::uint32_t, std::uint32_t>> edges;
  edges.reserve(mesh.triangles.size() * 3);
  for (const auto& t : mesh.triangles) {
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t a = t[k], b = t[(k + 1) % 3];
      edges.emplace_back(std::min(a, b), std::max(a, b));
    }
  }
  std::sort(edges.begin(), edges.end());
  edges.erase(std::unique(edges.begin(), edges.end()), edges.end());

  std::vector<Vec3> samples;
  samples.reserve(mesh.vertices.size() + edges.size() + mesh.triangles.size());
  samples.insert(samples.end(), mesh.vertices.begin(), mesh.vertices.end());
  for (const auto& [a, b] : edges) samples.push_back(0.5 * (mesh.vertices[a] + mesh.vertices[b]));
  for (const auto& t : mesh.triangles) {
    samples.push_back((mesh.vertices[t[0]] + mesh.vertices[t[1]] + mesh.vertices[t[2]]) / 3);
  }
  return samples;
}

SampleClusters clusterSamples(const std::vector<Vec3>& points, int cellsAlongLongest) {
  SampleClusters out;
  if (points.empty()) return out;
  Eigen::AlignedBox3d box;
  for (const Vec3& p : points) box.extend(p);
  const int cells =
      cellsAlongLongest > 0
          ? cellsAlongLongest
          : std::clamp(
                static_cast<int>(std::lround(std::sqrt(static_cast<double>(points.size()) / 24))),
                1, 8);
  const CellGrid grid(box, cells);
  std::vector<std::pair<std::size_t, std::uint32_t>> order;  // (cell, index): a stable sort
  order.reserve(points.size());
  for (std::uint32_t i = 0; i < points.size(); ++i) order.emplace_back(grid.cellOf(points[i]), i);
  std::sort(order.begin(), order.end());
  out.points.reserve(points.size());
  for (std::size_t i = 0; i < order.size();) {
    SampleClusters::Cluster c;
    c.begin = static_cast<std::uint32_t>(out.points.size());
    Eigen::AlignedBox3d bounds;
    std::size_t j = i;
    for (; j < order.size() && order[j].first == order[i].first; ++j) {
      out.points.push_back(points[order[j].second]);
      bounds.extend(out.points.back());
    }
    c.end = static_cast<std::uint32_t>(out.points.size());
    c.centre = bounds.center();
    for (std::uint32_t m = c.begin; m < c.end; ++m)
      c.radius = std::max(c.radius, (out.points[m] - c.centre).norm());
    out.clusters.push_back(c);
    i = j;
  }
  return out;
}

}  // namespace vf

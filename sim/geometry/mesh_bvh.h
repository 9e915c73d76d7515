// A bounding-volume hierarchy over the triangles of a closed mesh, for exact point queries
// in O(log n) instead of O(n): the nearest surface point, its distance, and whether the point
// is inside. Diagnostics use it (true-mesh interpenetration and tunnelling); the collision
// pipeline never does.
//
// Inside/outside comes from the angle-weighted pseudonormal of the nearest feature (face, edge
// or vertex) (Baerentzen and Aanaes, "Signed distance computation using the angle weighted
// pseudonormal", IEEE TVCG 2005): for a closed, consistently oriented, manifold mesh (what
// validateClosedMesh accepts) p is inside iff (p - q) . n < 0, where q is the nearest surface
// point and n the pseudonormal of the feature q lies on. For such meshes this decides exactly
// what the generalised winding number (mesh_query.h, the brute-force reference) decides, away
// from the surface itself, where both are decided only up to round-off.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "sim/core/math.h"
#include "sim/geometry/tri_mesh.h"

namespace vf {

// Which part of a triangle a nearest point lies on.
enum class TriangleFeature : std::uint8_t {
  kFace,
  kEdge0,  // edge (v0, v1)
  kEdge1,  // edge (v1, v2)
  kEdge2,  // edge (v2, v0)
  kVertex0,
  kVertex1,
  kVertex2
};

// Closest point of the triangle (a, b, c) to p, and the feature it lies on (Voronoi regions:
// vertices, then edges, then the face).
Vec3 closestPointOnTriangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c,
                            TriangleFeature& feature);

class MeshBvh {
 public:
  // Builds the hierarchy of a closed, outward, manifold mesh (validateClosedMesh's contract).
  explicit MeshBvh(const TriMesh& mesh);

  struct Nearest {
    double distance = 0;  // m, unsigned distance to the surface
    bool inside = false;  // p strictly inside the solid (decided by the pseudonormal)
    Vec3 point = Vec3::Zero();
  };
  // Nearest surface point of p (mesh frame). With `enough` >= 0 the search stops at the first
  // surface point it finds within `enough` of p: such a result (distance <= enough) is a
  // surface point, not necessarily the nearest, and its `inside` means nothing; a result with
  // distance > enough is exactly what the full search gives (the search visits the same nodes
  // in the same order up to the stop).
  Nearest nearest(const Vec3& p, double enough = -1) const;
  // Bytes held by the hierarchy (nodes and per-triangle data).
  std::size_t memoryBytes() const;

 private:
  struct Node {
    Vec3 lo, hi;          // bounds of the triangles below
    std::uint32_t first;  // leaf: first triangle; inner: index of the left child (right = +1)
    std::uint32_t count;  // triangles in a leaf, 0 for an inner node
  };
  struct Triangle {
    Vec3 v[3];
    Vec3 faceNormal;                   // unit
    std::array<Vec3, 3> edgeNormal;    // pseudonormal of edge k (v_k, v_k+1): sum of the two faces
    std::array<Vec3, 3> vertexNormal;  // angle-weighted pseudonormal of vertex k
  };
  std::vector<Node> nodes_;
  std::vector<Triangle> triangles_;  // in leaf order
};

}  // namespace vf

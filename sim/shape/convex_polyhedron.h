// The features of a convex mesh for the polygon collider (the paper's "old method", digest
// section 7): its vertices, its triangles with their planes, its edges with the two triangles
// that meet there, and its flat faces (coplanar triangles merged into one convex polygon,
// used to clip a face-face contact). Built once per shape, immutable, shared.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "sim/core/math.h"
#include "sim/geometry/tri_mesh.h"

namespace vf {

struct ConvexPolyhedron {
  struct Edge {
    std::uint32_t v0 = 0, v1 = 0;  // vertex indices
    std::uint32_t t0 = 0, t1 = 0;  // the two triangles that share the edge
  };
  struct Face {                       // one flat face: coplanar triangles merged
    Vec3 normal = Vec3::UnitZ();      // outward, unit, body frame
    double offset = 0;                // normal . p = offset on the face, m
    std::vector<std::uint32_t> loop;  // boundary vertices, counter-clockwise about normal
  };
  std::vector<Vec3> vertices;  // body frame, m
  std::vector<std::array<std::uint32_t, 3>> triangles;
  std::vector<Vec3> triangleNormals;        // outward, unit
  std::vector<double> triangleOffsets;      // n . p on the triangle, m
  std::vector<std::uint32_t> triangleFace;  // which flat face holds each triangle
  std::vector<Edge> edges;                  // every mesh edge once
  std::vector<Face> faces;
  double boundingRadius = 0;  // largest vertex distance from the origin, m
};

// True if every vertex of the closed mesh lies on or behind every triangle's plane (within
// a tolerance of 1e-7 of the mesh size): the mesh bounds a convex solid.
bool isConvexMesh(const TriMesh& mesh);

// Builds the features of a closed, outward, convex mesh (body frame). Throws InputError at
// `where` naming `shapeName` when the mesh is not convex: the polygon method needs convexity.
ConvexPolyhedron buildConvexPolyhedron(const TriMesh& mesh, const std::string& shapeName,
                                       const std::string& where);

}  // namespace vf

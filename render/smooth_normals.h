// Vertex normals for smooth shading. A terrain grid is a sampled smooth surface: every vertex
// gets one normal. A body's mesh has hard edges as well as soft ones (a boulder's rounded
// flanks, a block's corners): creasedNormals() splits each vertex between the groups of faces
// around it that meet at no more than a crease angle, so soft edges shade smoothly and hard
// ones stay sharp (the smoothing-angle rule of 3D modelling tools).
#pragma once

#include <vector>

#include "sim/core/math.h"
#include "sim/geometry/tri_mesh.h"

namespace vf {

// Per-vertex normals of a mesh with shared vertices: the mean of the normals of the triangles
// around each vertex, weighted by their angles there (for smooth shading of terrain grids). A
// vertex in no triangle gets +z.
std::vector<Vec3> smoothVertexNormals(const TriMesh& mesh);

// A mesh ready for smooth shading: vertices split where faces meet at a crease, one normal each.
struct CreasedMesh {
  TriMesh mesh;               // the triangles in their order, re-indexed to the split vertices
  std::vector<Vec3> normals;  // unit, one per vertex of `mesh`
};

// Around each vertex, triangles that share an edge through it and whose face normals differ
// by at most `creaseDegrees` are joined (and so are the groups they chain into); each group
// gets its own copy of the vertex with the angle-weighted mean normal of its triangles (as
// smoothVertexNormals). 0 keeps only coplanar neighbours together (flat shading); 180 joins
// every face around a vertex. A degenerate triangle is a group of its own, with normal +z.
CreasedMesh creasedNormals(const TriMesh& mesh, double creaseDegrees);

}  // namespace vf

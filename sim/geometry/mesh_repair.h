// Repair of meshes that are almost closed (a scan with small holes, a CAD export with a missing
// or flipped triangle), asked for with `repair = true` on a shape or `--repair`. CGAL is seen
// only in mesh_repair.cpp (and convex_hull.cpp).
#pragma once

#include <cstddef>
#include <string>

#include "sim/geometry/tri_mesh.h"

namespace vf {

// What repair may change. A hole is filled only when both bounds hold; a larger one is refused,
// because a patch that big would be a guess about the body's shape (and its mass).
struct RepairLimits {
  std::size_t maxHoleEdges = 200;     // boundary-loop length, edges
  double maxHoleAreaFraction = 0.05;  // a patch's area over the repaired mesh's surface
};

// What repair did, for the message the user sees.
struct RepairReport {
  std::size_t duplicateTriangles = 0;   // removed (same three vertices as another triangle)
  std::size_t degenerateTriangles = 0;  // zero-area triangles removed (edges collapsed)
  std::size_t reorientedTriangles = 0;  // turned to wind like their neighbours
  std::size_t holesFilled = 0;
  std::size_t patchTriangles = 0;   // triangles added to fill the holes
  double patchArea = 0;             // their total area, in the mesh's units squared
  double largestPatchFraction = 0;  // the largest patch over the surface area
  bool flippedInsideOut = false;    // the whole mesh faced inwards
  // "filled 3 holes with 27 triangles (largest 0.8 % of the surface), removed 2 duplicate
  // triangles, ..." or "nothing to repair".
  std::string summary() const;
};

// Returns the repaired mesh: duplicate and degenerate triangles removed, winding made
// consistent and outward, holes within `limits` filled (CGAL's polygon mesh processing:
// polygon-soup repair and orientation, degenerate-face removal, border stitching, minimal-area
// hole triangulation). Throws InputError at `where` naming the hole that is too large, or if
// the result is still not a closed manifold. The input is not modified.
TriMesh repairMesh(const TriMesh& mesh, const std::string& where, RepairReport& report,
                   const RepairLimits& limits = {});

}  // namespace vf

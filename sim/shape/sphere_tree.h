// The voxel sphere tree of one mesh (section 3, figs. 1-4).
//
// Level 0 is one cube enclosing the mesh; level k halves the edge, so its voxels have edge
// a_k = a_0 / 2^k. Only SURFACE voxels are kept (exact triangle/box overlap), each represented
// by its circumscribed sphere (radius a_k * sqrt(3) / 2, centre at the voxel centre), fixed in
// the body frame. A voxel's children are its surface sub-voxels at the next level, stored
// contiguously, so a level is a flat array and a node's children are a range of the next one.
//
// A voxel's circumscribed sphere contains the spheres of its eight sub-voxels (they touch it
// from inside), so "children overlap" implies "parents overlap": the descent of fig. 3 finds
// exactly the leaf pairs a brute-force test of all leaf spheres would find.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "sim/core/math.h"
#include "sim/geometry/tri_mesh.h"

namespace vf {

struct SphereTreeLevel {
  double edge = 0;                        // voxel edge a_k, m
  double radius = 0;                      // circumscribed sphere radius a_k sqrt(3)/2, m
  std::vector<Vec3> centers;              // body frame, one per surface voxel
  std::vector<std::uint32_t> childBegin;  // size centers.size()+1: children of node i are
                                          // [childBegin[i], childBegin[i+1]) of the next level;
                                          // empty (all zero) on the leaf level
  // The centres again in single precision, as structure of arrays: x of every node, then y,
  // then z, each block floatStride() = centers.size() + kFloatPad long and zero-padded, so that
  // the children of any node (at most 8, contiguous) load as 8 lanes. Only for pruning tests
  // that are widened by their rounding (the tree-tree descent, tree_tree_descent.cpp). Filled by
  // finishSphereTree.
  static constexpr std::size_t kFloatPad = 8;
  std::vector<float> floatCenters;
  std::size_t floatStride() const { return centers.size() + kFloatPad; }
  const float* floatAxis(int d) const {  // coordinate d (0: x, 1: y, 2: z) of every node
    return floatCenters.data() + d * floatStride();
  }
};

struct SphereTree {
  std::vector<SphereTreeLevel> levels;  // levels[0] .. levels[leafLevel()]
  double boundingRadius = 0;  // sphere about the body origin that encloses every leaf sphere
  double centerBound = 0;     // bound on |c| of every node centre c, of every level
  int leafLevel() const { return static_cast<int>(levels.size()) - 1; }
  const SphereTreeLevel& leaves() const { return levels.back(); }
  std::size_t memoryBytes() const;  // of the levels' arrays, as allocated
};

constexpr int kMinLevel = 1;
constexpr int kMaxLevel = 10;

// Builds the tree of `mesh` (given in the body frame) down to `leafLevel` (kMinLevel ..
// kMaxLevel). The level-0 cube is centred on the mesh bounds, with edge = the largest extent
// enlarged by a relative 1e-9 so faces lying on the bounds fall inside the outer voxel layer.
// Children are visited in a fixed (z, y, x) order: the result is deterministic.
SphereTree buildSphereTree(const TriMesh& mesh, int leafLevel);

// Fills what follows from a tree's levels: boundingRadius, centerBound and each level's float
// centres. buildSphereTree calls it; a tree whose levels are filled by hand needs it too.
void finishSphereTree(SphereTree& tree);

}  // namespace vf

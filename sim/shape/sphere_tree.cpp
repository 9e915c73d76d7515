// Voxel sphere tree construction (section 3, figs. 1-2).
//
// Depth-first subdivision: a surface voxel is split into its 8 sub-voxels, visited in the
// fixed order index = 4*iz + 2*iy + ix; a sub-voxel is kept if some triangle that overlaps the
// parent also overlaps it (a triangle that misses the parent misses every child, so each node
// only tests its parent's triangle list: building costs about (triangles x levels), not
// (triangles x voxels)). All kept children of a node are appended to the next level before
// any of them is expanded; since the nodes of each level are then expanded in the order they
// were appended, each node's children form one contiguous range and the ranges are
// increasing. This gives the same arrays as a breadth-first build with only one triangle list
// per depth alive at a time.
//
// Voxel centres come from integer grid coordinates (origin + (i + 1/2) a_k with
// a_k = a_0 / 2^k exact), so siblings and parents agree to the last bit on their shared grid.
#include "sim/shape/sphere_tree.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#include "sim/core/error.h"
#include "sim/shape/voxelize.h"

namespace vf {
namespace {

using Coord = std::array<std::uint32_t, 3>;

struct Triangle {
  Vec3 a, b, c;
  Vec3 lo, hi;  // bounding box, for the cheap child pre-selection
};

class Builder {
 public:
  Builder(const TriMesh& mesh, int leafLevel, SphereTree& tree) : leaf_(leafLevel), tree_(tree) {
    const Eigen::AlignedBox3d box = mesh.bounds();
    // Relative 1e-9 enlargement: faces lying on the bounds fall strictly inside the outer
    // voxel layer instead of on the root cube's faces.
    edge0_ = box.sizes().maxCoeff() * (1 + 1e-9);
    VF_ASSERT(edge0_ > 0 && std::isfinite(edge0_));
    origin_ = box.center() - Vec3::Constant(edge0_ / 2);
    tris_.reserve(mesh.triangles.size());
    for (const auto& t : mesh.triangles) {
      Triangle tri{mesh.vertices[t[0]], mesh.vertices[t[1]], mesh.vertices[t[2]], {}, {}};
      tri.lo = tri.a.cwiseMin(tri.b).cwiseMin(tri.c);
      tri.hi = tri.a.cwiseMax(tri.b).cwiseMax(tri.c);
      tris_.push_back(tri);
    }
    tree_.levels.resize(leaf_ + 1);
    for (int k = 0; k <= leaf_; ++k) {
      tree_.levels[k].edge = std::ldexp(edge0_, -k);
      tree_.levels[k].radius = tree_.levels[k].edge * std::sqrt(3.0) / 2;
    }
    scratch_.resize(leaf_);
  }

  void build() {
    std::vector<std::uint32_t> all(tris_.size());
    for (std::uint32_t i = 0; i < all.size(); ++i) all[i] = i;
    tree_.levels[0].centers.push_back(center(0, {0, 0, 0}));
    expand(0, 0, {0, 0, 0}, all);
    for (int k = 0; k < leaf_; ++k) {
      tree_.levels[k].childBegin.push_back(
          static_cast<std::uint32_t>(tree_.levels[k + 1].centers.size()));
    }
    tree_.levels[leaf_].childBegin.assign(tree_.levels[leaf_].centers.size() + 1, 0);
  }

 private:
  Vec3 center(int level, const Coord& c) const {
    const double a = tree_.levels[level].edge;
    return origin_ + a * (Vec3(c[0], c[1], c[2]) + Vec3::Constant(0.5));
  }

  // Appends the surface children of node (level, coord), whose triangle list is `tris`, then
  // expands each of them.
  void expand(int level, std::uint32_t node, const Coord& coord,
              const std::vector<std::uint32_t>& tris) {
    if (level == leaf_) return;
    SphereTreeLevel& next = tree_.levels[level + 1];
    auto& lists = scratch_[level];
    const bool childIsLeaf = level + 1 == leaf_;
    const Vec3 split = center(level, coord);
    const double childEdge = next.edge;
    const Vec3 half = Vec3::Constant(childEdge / 2);
    // Loose pre-selection margin: SAT, not this test, decides; it only skips children the
    // triangle's bounding box clearly misses.
    const double margin = 1e-6 * childEdge;

    std::array<bool, 8> kept{};
    std::array<Coord, 8> childCoord{};
    std::array<Vec3, 8> childCenter;
    for (int i = 0; i < 8; ++i) {
      lists[i].clear();
      const int ix = i & 1, iy = (i >> 1) & 1, iz = (i >> 2) & 1;
      childCoord[i] = {2 * coord[0] + ix, 2 * coord[1] + iy, 2 * coord[2] + iz};
      childCenter[i] = center(level + 1, childCoord[i]);
    }
    for (std::uint32_t t : tris) {
      const Triangle& tri = tris_[t];
      // Which halves along each axis the triangle's box reaches (bit 0: low, bit 1: high).
      int reach[3];
      for (int d = 0; d < 3; ++d) {
        reach[d] =
            (tri.lo[d] <= split[d] + margin ? 1 : 0) | (tri.hi[d] >= split[d] - margin ? 2 : 0);
      }
      for (int i = 0; i < 8; ++i) {
        const int ix = i & 1, iy = (i >> 1) & 1, iz = (i >> 2) & 1;
        if (!(reach[0] & (1 << ix)) || !(reach[1] & (1 << iy)) || !(reach[2] & (1 << iz))) continue;
        if (childIsLeaf && kept[i]) continue;  // a leaf only needs one witness
        if (triangleBoxOverlap(childCenter[i], half, tri.a, tri.b, tri.c)) {
          kept[i] = true;
          if (!childIsLeaf) lists[i].push_back(t);
        }
      }
    }

    tree_.levels[level].childBegin.push_back(static_cast<std::uint32_t>(next.centers.size()));
    VF_ASSERT(tree_.levels[level].childBegin.size() == node + 1);
    std::array<std::uint32_t, 8> childIndex{};
    for (int i = 0; i < 8; ++i) {
      if (!kept[i]) continue;
      childIndex[i] = static_cast<std::uint32_t>(next.centers.size());
      next.centers.push_back(childCenter[i]);
    }
    if (childIsLeaf) return;
    for (int i = 0; i < 8; ++i) {
      if (kept[i]) expand(level + 1, childIndex[i], childCoord[i], lists[i]);
    }
  }

  int leaf_;
  SphereTree& tree_;
  double edge0_ = 0;
  Vec3 origin_;
  std::vector<Triangle> tris_;
  // Per depth, the 8 children's triangle lists; reused so deep levels do not allocate per node.
  std::vector<std::array<std::vector<std::uint32_t>, 8>> scratch_;
};

}  // namespace

SphereTree buildSphereTree(const TriMesh& mesh, int leafLevel) {
  VF_ASSERT(leafLevel >= kMinLevel && leafLevel <= kMaxLevel);
  VF_ASSERT(!mesh.triangles.empty());
  SphereTree tree;
  Builder(mesh, leafLevel, tree).build();
  finishSphereTree(tree);
  return tree;
}

void finishSphereTree(SphereTree& tree) {
  VF_ASSERT(!tree.levels.empty() && !tree.levels[0].centers.empty());
  // The body's bounding sphere (fig. 3, step 1): about the body origin, enclosing every leaf
  // sphere, hence every deeper test.
  const SphereTreeLevel& leaves = tree.leaves();
  double farthest = 0;
  for (const Vec3& c : leaves.centers) farthest = std::max(farthest, c.norm());
  tree.boundingRadius = farthest + leaves.radius;
  // Every node centre lies in the level-0 cube, so within its circumscribed sphere.
  const SphereTreeLevel& root = tree.levels[0];
  tree.centerBound = root.centers[0].norm() + root.radius;
  for (SphereTreeLevel& lv : tree.levels) {
    const std::size_t stride = lv.floatStride();
    lv.floatCenters.assign(3 * stride, 0.0f);
    for (std::size_t i = 0; i < lv.centers.size(); ++i)
      for (int d = 0; d < 3; ++d)
        lv.floatCenters[d * stride + i] = static_cast<float>(lv.centers[i][d]);
  }
}

std::size_t SphereTree::memoryBytes() const {
  std::size_t bytes = 0;
  for (const SphereTreeLevel& lv : levels)
    bytes += lv.centers.capacity() * sizeof(Vec3) +
             lv.childBegin.capacity() * sizeof(std::uint32_t) +
             lv.floatCenters.capacity() * sizeof(float);
  return bytes;
}

}  // namespace vf

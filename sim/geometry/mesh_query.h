// Geometric queries on a closed mesh, used by diagnostics (true-mesh interpenetration and
// tunnelling), never inside the collision pipeline.
#pragma once

#include <cstdint>
#include <vector>

#include "sim/core/math.h"
#include "sim/geometry/tri_mesh.h"

namespace vf {

// True if p is strictly inside the closed mesh (generalised winding number > 1/2).
bool pointInsideMesh(const TriMesh& mesh, const Vec3& p);

// Unsigned distance from p to the nearest point of the mesh surface.
double distanceToMesh(const TriMesh& mesh, const Vec3& p);

// Points on the surface for penetration sampling: every vertex, every edge midpoint and every
// triangle centroid.
std::vector<Vec3> surfaceSamples(const TriMesh& mesh);

// Points grouped into compact clusters, each with a bounding sphere, so that a test against a
// box can drop a whole cluster by its sphere instead of moving every point into the box's frame.
struct SampleClusters {
  struct Cluster {
    Vec3 centre = Vec3::Zero();
    double radius = 0;        // every point of the cluster within this of the centre
    std::uint32_t begin = 0;  // the cluster's points: points[begin, end)
    std::uint32_t end = 0;
  };
  std::vector<Vec3> points;  // the points given, grouped by cluster
  std::vector<Cluster> clusters;
};

// Groups points by the cells of a grid of `cellsAlongLongest` cubes along the longest side of
// their bounds (empty cells make no cluster); in cell order, and in the given order within a
// cell, so the result depends only on the points. 0 chooses it from the count: round(sqrt(n /
// 24)), 1 to 8, about 4 points a cluster for points on a surface, which fills some 6 k^2 of the
// k^3 cells (a box's 38 samples make one cluster; highpoly's block, 578, a 5-cell grid). Measured
// on sim_bench's scenes, fixed 4 cells cost the small meshes more than they saved.
SampleClusters clusterSamples(const std::vector<Vec3>& points, int cellsAlongLongest = 0);

}  // namespace vf

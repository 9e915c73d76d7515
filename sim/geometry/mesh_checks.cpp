// Closed-mesh validation for rigid bodies. The mass properties (divergence theorem) and the
// inside/outside notion of the voxel surface are only meaningful for a watertight, manifold,
// consistently oriented mesh, so a bad mesh is rejected at the boundary with a message that
// says what is wrong, how often, one example, and what to do.
//
// Topology is checked on directed edges: every triangle (a, b, c) contributes a->b, b->c,
// c->a. Sorted by undirected key, a closed consistently oriented manifold has exactly two uses
// per edge, in opposite directions. Sorting (rather than hashing) keeps the reported example
// deterministic: it is the edge with the smallest vertex indices.
#include "sim/geometry/mesh_checks.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <string>
#include <utility>
#include <vector>

#include "sim/core/error.h"

namespace vf {
namespace {

// Relative thresholds. Round-off in a triangle's area is ~1e-16 diag^2, in the enclosed
// volume ~1e-16 * (triangle count) * diag^3, so both are far below these; a real body is many
// orders above them.
constexpr double kDegenerateAreaRel = 1e-12;  // area < this * diag^2: degenerate
constexpr double kFlatVolumeRel = 1e-9;       // |volume| < this * diag^3: no volume

std::string shortNumber(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3g", x);
  return buf;
}

std::string plural(std::size_t n, const std::string& word) {
  return std::to_string(n) + " " + word + (n == 1 ? "" : "s");
}

struct DirectedEdge {
  std::uint32_t lo, hi;  // undirected key, lo < hi
  bool forward;          // true if the triangle traverses lo -> hi
  bool operator<(const DirectedEdge& o) const {
    return lo != o.lo ? lo < o.lo : hi != o.hi ? hi < o.hi : forward < o.forward;
  }
};

// The mesh's problem edges, counted, each kind with its first example (in edge order).
struct EdgeProblems {
  std::size_t boundary = 0, nonManifold = 0, misoriented = 0;
  std::pair<std::uint32_t, std::uint32_t> exBoundary{}, exNonManifold{}, exMisoriented{};
};

EdgeProblems edgeProblems(const TriMesh& mesh) {
  std::vector<DirectedEdge> edges;
  edges.reserve(mesh.triangles.size() * 3);
  for (const auto& t : mesh.triangles) {
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t a = t[k], b = t[(k + 1) % 3];
      edges.push_back({std::min(a, b), std::max(a, b), a < b});
    }
  }
  std::sort(edges.begin(), edges.end());

  EdgeProblems p;
  for (std::size_t i = 0; i < edges.size();) {
    std::size_t j = i;
    while (j < edges.size() && edges[j].lo == edges[i].lo && edges[j].hi == edges[i].hi) ++j;
    const std::size_t uses = j - i;
    const std::pair<std::uint32_t, std::uint32_t> e{edges[i].lo, edges[i].hi};
    if (uses == 1) {
      if (p.boundary++ == 0) p.exBoundary = e;
    } else if (uses > 2) {
      if (p.nonManifold++ == 0) p.exNonManifold = e;
    } else if (edges[i].forward == edges[i + 1].forward) {
      if (p.misoriented++ == 0) p.exMisoriented = e;
    }
    i = j;
  }
  return p;
}

void checkTopology(const TriMesh& mesh, const std::string& where) {
  const auto [boundary, nonManifold, misoriented, exBoundary, exNonManifold, exMisoriented] =
      edgeProblems(mesh);

  auto edgeName = [](std::pair<std::uint32_t, std::uint32_t> e) {
    return "vertices " + std::to_string(e.first) + " and " + std::to_string(e.second);
  };
  // The first problem found is the headline; the others are listed so one run shows them all.
  std::string others;
  auto addOther = [&](std::size_t n, const std::string& what) {
    if (n == 0) return;
    others += others.empty() ? " (also " : ", ";
    others += plural(n, what);
  };
  if (boundary > 0) {
    addOther(nonManifold, "non-manifold edge");
    addOther(misoriented, "inconsistently oriented edge");
    if (!others.empty()) others += ")";
    throw InputError(where, "mesh is not closed: " + plural(boundary, "boundary edge") +
                                " (used by one triangle only), e.g. between " +
                                edgeName(exBoundary) + others +
                                "; rigid bodies need a watertight mesh: fill the holes");
  }
  if (nonManifold > 0) {
    addOther(misoriented, "inconsistently oriented edge");
    if (!others.empty()) others += ")";
    throw InputError(where, "mesh is not manifold: " + plural(nonManifold, "edge") +
                                " shared by more than two triangles, e.g. between " +
                                edgeName(exNonManifold) + others +
                                "; separate the touching parts or merge them into one surface");
  }
  if (misoriented > 0) {
    throw InputError(where, "mesh is inconsistently oriented: " + plural(misoriented, "edge") +
                                " where both triangles run the same way, e.g. between " +
                                edgeName(exMisoriented) +
                                "; make all triangles wind counter-clockwise seen from outside");
  }
}

}  // namespace

void validateClosedMesh(TriMesh& mesh, const std::string& where) {
  if (mesh.triangles.size() < 4) {
    throw InputError(where, "mesh has " + plural(mesh.triangles.size(), "triangle") +
                                "; a closed mesh needs at least 4");
  }
  for (std::size_t i = 0; i < mesh.vertices.size(); ++i) {
    if (!mesh.vertices[i].allFinite())
      throw InputError(where, "vertex " + std::to_string(i) + " has a non-finite coordinate");
  }
  for (std::size_t i = 0; i < mesh.triangles.size(); ++i) {
    for (std::uint32_t v : mesh.triangles[i]) {
      if (v >= mesh.vertices.size())
        throw InputError(where, "triangle " + std::to_string(i) + " refers to vertex " +
                                    std::to_string(v) + " but the mesh has only " +
                                    plural(mesh.vertices.size(), "vertex"));
    }
  }

  const double diagonal = mesh.bounds().diagonal().norm();
  const Vec3 ref = mesh.bounds().center();  // reference point near the mesh: small round-off

  // Degenerate triangles: zero area relative to the mesh scale (also catches repeated indices).
  std::size_t degenerate = 0, exDegenerate = 0;
  const double minDoubleArea = 2 * kDegenerateAreaRel * diagonal * diagonal;
  for (std::size_t i = 0; i < mesh.triangles.size(); ++i) {
    const auto& t = mesh.triangles[i];
    const Vec3& a = mesh.vertices[t[0]];
    const double doubleArea = (mesh.vertices[t[1]] - a).cross(mesh.vertices[t[2]] - a).norm();
    if (!(doubleArea >= minDoubleArea) && degenerate++ == 0) exDegenerate = i;
  }
  if (degenerate > 0) {
    const auto& t = mesh.triangles[exDegenerate];
    throw InputError(where, "mesh has " + plural(degenerate, "degenerate (zero-area) triangle") +
                                ", e.g. triangle " + std::to_string(exDegenerate) + " (vertices " +
                                std::to_string(t[0]) + ", " + std::to_string(t[1]) + ", " +
                                std::to_string(t[2]) + "); remove them and close the mesh again");
  }

  checkTopology(mesh, where);

  // Enclosed volume (divergence theorem, signed tetrahedra from `ref`).
  double volume6 = 0;
  for (const auto& t : mesh.triangles) {
    const Vec3 a = mesh.vertices[t[0]] - ref, b = mesh.vertices[t[1]] - ref,
               c = mesh.vertices[t[2]] - ref;
    volume6 += a.dot(b.cross(c));
  }
  const double volume = volume6 / 6;
  if (!(std::abs(volume) >= kFlatVolumeRel * diagonal * diagonal * diagonal)) {
    throw InputError(where, "mesh encloses no volume (" + shortNumber(volume) +
                                " for a bounding box diagonal of " + shortNumber(diagonal) +
                                "): it is flat; a rigid body needs a solid");
  }
  // Inward triangles describe the same solid: flip them rather than reject the file.
  if (volume < 0) {
    for (auto& t : mesh.triangles) std::swap(t[1], t[2]);
  }
}

}  // namespace vf

// Mesh files to TriMesh through assimp: the only file in voxfall that includes assimp.
//
// Design: assimp is asked only to triangulate polygons. Its own vertex joining
// (aiProcess_JoinIdenticalVertices) is NOT used: it compares whole vertices (position, normal,
// uv), so a cube with per-face normals stays split into 24 vertices and looks open, and it can
// also hide real topology faults. Instead every triangle corner is welded here by position
// alone, on a grid of cell 1e-9 * (bounding box diagonal), visiting meshes in scene-graph
// order and looking keys up in an ordered map, so the result does not depend on hashing.
#include "sim/geometry/mesh_import.h"

#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <array>
#include <assimp/Importer.hpp>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "sim/core/error.h"
#include "sim/geometry/ply_check.h"

namespace vf {
namespace {

// Welding tolerance relative to the bounding box diagonal. It is below float precision
// (~6e-8), so in practice only corners the file stores at the same position are joined:
// distinct vertices are never merged, and a crack in a scan stays a crack for the checks.
constexpr double kWeldRelTolerance = 1e-9;

// One triangle soup: three corners per triangle, in file units, node transforms applied.
struct Soup {
  std::vector<Vec3> corners;
};

// Converts assimp's single-precision matrix to double so the transform is applied without
// further rounding of the (float) file coordinates.
Eigen::Matrix4d toEigen(const aiMatrix4x4& m) {
  Eigen::Matrix4d r;
  r << m.a1, m.a2, m.a3, m.a4, m.b1, m.b2, m.b3, m.b4, m.c1, m.c2, m.c3, m.c4, m.d1, m.d2, m.d3,
      m.d4;
  return r;
}

// Depth-first over the node graph in child order (deterministic), accumulating transforms.
void collectNode(const aiScene& scene, const aiNode& node, const Eigen::Matrix4d& parent,
                 Soup& soup) {
  const Eigen::Matrix4d world = parent * toEigen(node.mTransformation);
  const Eigen::Matrix3d linear = world.topLeftCorner<3, 3>();
  const Vec3 offset = world.topRightCorner<3, 1>();
  // A mirroring transform turns counter-clockwise triangles clockwise (glTF states this
  // explicitly for negative-determinant nodes): swap two corners to keep them outward.
  const bool mirrored = linear.determinant() < 0;
  for (unsigned mi = 0; mi < node.mNumMeshes; ++mi) {
    const aiMesh& mesh = *scene.mMeshes[node.mMeshes[mi]];
    for (unsigned fi = 0; fi < mesh.mNumFaces; ++fi) {
      const aiFace& face = mesh.mFaces[fi];
      if (face.mNumIndices != 3) continue;  // points and lines carry no volume
      std::array<Vec3, 3> p;
      for (int k = 0; k < 3; ++k) {
        const aiVector3D& v = mesh.mVertices[face.mIndices[k]];
        p[k] = linear * Vec3(v.x, v.y, v.z) + offset;
      }
      if (mirrored) std::swap(p[1], p[2]);
      soup.corners.insert(soup.corners.end(), p.begin(), p.end());
    }
  }
  for (unsigned ci = 0; ci < node.mNumChildren; ++ci)
    collectNode(scene, *node.mChildren[ci], world, soup);
}

using GridKey = std::array<std::int64_t, 3>;

// Welds corners that lie within one grid cell (or a neighbouring one, within the tolerance)
// into one vertex; the first corner seen gives the vertex its position.
TriMesh weld(const Soup& soup) {
  Eigen::AlignedBox3d box;
  for (const Vec3& p : soup.corners) box.extend(p);
  const double diagonal = box.diagonal().norm();
  const double cell = diagonal > 0 ? kWeldRelTolerance * diagonal : 1.0;
  // Keys relative to the box minimum stay below ~1e9: no int64 overflow even far from the origin.
  auto keyOf = [&](const Vec3& p) {
    const Vec3 q = (p - box.min()) / cell;
    return GridKey{std::llround(q.x()), std::llround(q.y()), std::llround(q.z())};
  };

  TriMesh mesh;
  std::map<GridKey, std::uint32_t> index;
  std::vector<std::uint32_t> ids(soup.corners.size());
  for (std::size_t i = 0; i < soup.corners.size(); ++i) {
    const Vec3& p = soup.corners[i];
    const GridKey key = keyOf(p);
    auto it = index.find(key);
    if (it == index.end()) {
      // Two corners within the tolerance may round to adjacent cells: look there too, in a
      // fixed order.
      for (int dz = -1; dz <= 1 && it == index.end(); ++dz)
        for (int dy = -1; dy <= 1 && it == index.end(); ++dy)
          for (int dx = -1; dx <= 1 && it == index.end(); ++dx) {
            auto n = index.find(GridKey{key[0] + dx, key[1] + dy, key[2] + dz});
            if (n != index.end() && (mesh.vertices[n->second] - p).norm() <= cell) it = n;
          }
    }
    if (it == index.end()) {
      it = index.emplace(key, static_cast<std::uint32_t>(mesh.vertices.size())).first;
      mesh.vertices.push_back(p);
    }
    ids[i] = it->second;
  }
  mesh.triangles.reserve(soup.corners.size() / 3);
  for (std::size_t t = 0; t + 2 < ids.size(); t += 3)
    mesh.triangles.push_back({ids[t], ids[t + 1], ids[t + 2]});
  return mesh;
}

}  // namespace

TriMesh importMesh(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec))
    throw InputError(path, "no such file (or not a regular file)");
  checkPlyLayout(path);  // assimp 5.2 trusts a PLY file's counts (ply_check.h)

  Assimp::Importer importer;
  // Triangulate only; no vertex joining, no degenerate removal (validateClosedMesh reports
  // those problems instead of having them silently "repaired").
  const aiScene* scene = importer.ReadFile(path, aiProcess_ValidateDataStructure);
  if (scene == nullptr)
    throw InputError(path, std::string("cannot read mesh: ") + importer.GetErrorString());
  // Each mesh's primitive types set from its faces before triangulating, and a face without
  // vertices refused: assimp 5.2's PLY reader makes one from a garbled face line (found by
  // mesh_ply_fuzz), its validation lets it through, and its triangulation, counting it as a
  // polygon, aborts the process on an assertion. The scene is the importer's own; setting the
  // types is the bookkeeping its post-processing steps keep themselves.
  for (unsigned m = 0; m < scene->mNumMeshes; ++m) {
    aiMesh& mesh = *const_cast<aiMesh*>(scene->mMeshes[m]);
    unsigned types = 0;
    for (unsigned f = 0; f < mesh.mNumFaces; ++f) {
      const unsigned n = mesh.mFaces[f].mNumIndices;
      if (n == 0)
        throw InputError(path, "cannot read mesh: face " + std::to_string(f) + " of mesh " +
                                   std::to_string(m) + " has no vertices");
      types |= n == 1   ? aiPrimitiveType_POINT
               : n == 2 ? aiPrimitiveType_LINE
               : n == 3 ? aiPrimitiveType_TRIANGLE
                        : aiPrimitiveType_POLYGON;
    }
    mesh.mPrimitiveTypes = types;
  }
  scene = importer.ApplyPostProcessing(aiProcess_Triangulate);
  if (scene == nullptr)
    throw InputError(path, std::string("cannot read mesh: ") + importer.GetErrorString());
  if ((scene->mFlags & AI_SCENE_FLAGS_INCOMPLETE) != 0 || scene->mRootNode == nullptr)
    throw InputError(path, "cannot read mesh: the file holds no complete scene");

  Soup soup;
  collectNode(*scene, *scene->mRootNode, Eigen::Matrix4d::Identity(), soup);
  if (soup.corners.empty())
    throw InputError(path, "no triangles in the file (only points, lines or nothing)");
  // The weld grid needs finite coordinates and a finite extent (a fuzz input: a NaN in a binary
  // STL makes the grid keys overflow).
  Eigen::AlignedBox3d box;
  for (std::size_t i = 0; i < soup.corners.size(); ++i) {
    if (!soup.corners[i].allFinite())
      throw InputError(path, "triangle " + std::to_string(i / 3) +
                                 " has a non-finite coordinate (NaN or infinity)");
    box.extend(soup.corners[i]);
  }
  if (!std::isfinite(box.diagonal().norm()))
    throw InputError(path, "coordinates span more than a double can hold");
  return weld(soup);
}

}  // namespace vf

// A triangle mesh in GPU memory, uploaded once and drawn many times.
#pragma once

#include <vector>

#include "sim/core/math.h"
#include "sim/geometry/tri_mesh.h"

namespace vf::gl {

struct Api;

class GpuMesh {
 public:
  // Uploads the triangles with per-vertex `normals` when given (smooth shading), otherwise with
  // each triangle's own normal on its three corners, so faceted rocks and blocks look faceted.
  GpuMesh(const Api& api, const TriMesh& mesh, const std::vector<Vec3>* normals);
  ~GpuMesh();
  GpuMesh(const GpuMesh&) = delete;
  GpuMesh& operator=(const GpuMesh&) = delete;

  // Draws all triangles (attribute 0: position, 1: normal; both in the mesh frame).
  void draw() const;
  int vertexCount() const { return vertexCount_; }

 private:
  const Api* api_;
  unsigned vao_ = 0;
  unsigned vbo_ = 0;
  int vertexCount_ = 0;
};

}  // namespace vf::gl

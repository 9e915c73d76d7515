#include "render/gl/gpu_mesh.h"

#include <cstddef>

#include "render/gl/gl_api.h"

namespace vf::gl {

GpuMesh::GpuMesh(const Api& api, const TriMesh& mesh, const std::vector<Vec3>* normals)
    : api_(&api) {
  // Unindexed: flat shading needs each corner's normal per triangle anyway, and meshes are
  // small next to the frame's pixels.
  std::vector<float> data;
  data.reserve(mesh.triangles.size() * 3 * 6);
  const bool smooth = normals && normals->size() == mesh.vertices.size();
  for (const auto& tri : mesh.triangles) {
    const Vec3& a = mesh.vertices[tri[0]];
    const Vec3& b = mesh.vertices[tri[1]];
    const Vec3& c = mesh.vertices[tri[2]];
    Vec3 face = (b - a).cross(c - a);
    // A degenerate triangle covers no pixels; any unit normal keeps the shader finite.
    face = face.norm() > 0 ? Vec3(face.normalized()) : Vec3(Vec3::UnitZ());
    for (std::uint32_t index : tri) {
      const Vec3& p = mesh.vertices[index];
      const Vec3 n = smooth ? Vec3((*normals)[index].normalized()) : face;
      data.insert(data.end(), {static_cast<float>(p.x()), static_cast<float>(p.y()),
                               static_cast<float>(p.z()), static_cast<float>(n.x()),
                               static_cast<float>(n.y()), static_cast<float>(n.z())});
    }
  }
  vertexCount_ = static_cast<int>(mesh.triangles.size() * 3);
  api.GenVertexArrays(1, &vao_);
  api.GenBuffers(1, &vbo_);
  api.BindVertexArray(vao_);
  api.BindBuffer(GL_ARRAY_BUFFER, vbo_);
  api.BufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(data.size() * sizeof(float)), data.data(),
                 GL_STATIC_DRAW);
  const GLsizei stride = 6 * sizeof(float);
  api.VertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, stride, nullptr);
  api.VertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, stride,
                          reinterpret_cast<const void*>(3 * sizeof(float)));
  api.EnableVertexAttribArray(0);
  api.EnableVertexAttribArray(1);
  api.BindVertexArray(0);
}

GpuMesh::~GpuMesh() {
  api_->DeleteBuffers(1, &vbo_);
  api_->DeleteVertexArrays(1, &vao_);
}

void GpuMesh::draw() const {
  api_->BindVertexArray(vao_);
  api_->DrawArrays(GL_TRIANGLES, 0, vertexCount_);
}

}  // namespace vf::gl

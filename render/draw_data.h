// What the renderer draws, as plain data (no GL): meshes, instances with model matrices and
// colours, the ground, the camera and the sun. The renderer reads a DrawList and nothing else;
// DrawListBuilder (render/draw_list.h) makes one from a run's frames, and tests make their own.
#pragma once

#include <memory>
#include <optional>
#include <vector>

#include "render/camera.h"
#include "render/light.h"
#include "sim/core/math.h"
#include "sim/geometry/tri_mesh.h"
#include "sim/scene/drawing_spec.h"

namespace vf {

struct DrapeImage;  // sim/shape/drape_import.h

// A triangle mesh to draw, shared, not copied: the renderer uploads each key once.
struct DrawMesh {
  const void* key = nullptr;            // identity in the GPU cache: the Shape, or the terrain
  std::shared_ptr<const TriMesh> mesh;  // body frame (centre of mass at the origin) or world
  std::shared_ptr<const std::vector<Vec3>> normals;  // per-vertex smooth normals; null: faceted
  bool transient = false;  // made for this frame only (trails): uploaded, drawn, dropped
  // Back faces never seen, so they are culled: a closed surface wound outward (a body's shape)
  // seen from outside, or a terrain's walls and base, wound outward, whose insides lie under
  // its surface. llvmpipe shades every rasterised fragment, hidden or not, so they would cost
  // as much as the faces seen.
  bool closed = false;
};

// How an instance is shaded.
enum class Surface {
  body,     // colour lit by sun (with shadow), sky and fill light
  terrain,  // as body, with the colour turned towards rock on steep slopes
  unlit,    // the flat colour, no light, no shadow (overlays and read-back tests)
};

struct DrawInstance {
  int mesh = 0;                   // index into DrawList::meshes
  Mat4 model = Mat4::Identity();  // mesh frame -> world: [R(q) x; 0 1] for a body
  Color color{0.8f, 0.8f, 0.8f};  // linear RGB albedo
  Surface surface = Surface::body;
  bool castsShadow = true;
  // Identity across frames (the body id), so a frame can be compared with the last one when
  // bodies appear or leave; -1 for the rest (terrain, trails), matched by their order.
  int id = -1;
};

struct DrawList {
  std::vector<DrawMesh> meshes;
  std::vector<DrawInstance> instances;
  std::optional<double> groundHeight;  // z of the floor plane, m; none: no floor drawn
  CameraView camera;
  Vec3 sunDirection = Vec3(0.3, -0.4, 0.87).normalized();  // unit, towards the sun
  LightColors light;  // sun, sky and ambient light (render/light.h)
  // A picture draped on the instances with Surface::terrain (world x, y to texel by its
  // rectangle); null: they are coloured by slope.
  std::shared_ptr<const DrapeImage> drape;
  // Sphere around everything that casts a shadow: what the shadow map has to cover.
  Vec3 casterCentre = Vec3::Zero();
  double casterRadius = 1;
  // The floor fades into the sky between these distances from the camera (m); its grid
  // lines are 1 m apart with 0.1 m minor lines, so the picture shows scale.
  double groundFadeStart = 20;
  double groundFadeEnd = 60;
};

// What the GPU receives of a model matrix: the matrix and the one for normals (the inverse
// transpose of its linear part), both in single precision. Two model matrices with equal
// GpuTransforms draw the same pixels, however their doubles differ (a body at rest creeping
// by 1e-12 m).
struct GpuTransform {
  Eigen::Matrix4f model;
  Eigen::Matrix3f normal;
  bool operator==(const GpuTransform& o) const { return model == o.model && normal == o.normal; }
};
GpuTransform gpuTransform(const Mat4& model);

}  // namespace vf

// Camera and projection math for the renderer: plain Eigen, no GL, so it is unit-testable.
// Conventions: world is SI metres, z up; eye space looks down -z (OpenGL); clip-space depth
// is [-1, 1]; matrices act on column vectors.
#pragma once

#include <Eigen/Core>

#include "sim/core/math.h"

namespace vf {

using Mat4 = Eigen::Matrix4d;
using Vec4 = Eigen::Vector4d;

// A pinhole camera in world coordinates.
struct CameraView {
  Vec3 position = Vec3(4, -6, 3);  // m
  Vec3 lookAt = Vec3::Zero();      // m
  Vec3 up = Vec3::UnitZ();
  double fovYDegrees = 40;  // vertical field of view
  double nearPlane = 0.05;  // m
  double farPlane = 200;    // m

  // World -> eye.
  Mat4 viewMatrix() const;
  // Eye -> clip for an image of width/height = aspect.
  Mat4 projectionMatrix(double aspect) const;
};

// World -> eye for a camera at `eye` looking at `target`. When `up` is (nearly) parallel to the
// viewing direction another axis is used, so looking straight down still gives a valid matrix.
Mat4 lookAtMatrix(const Vec3& eye, const Vec3& target, const Vec3& up);
// Eye -> clip, perspective; fovY in radians.
Mat4 perspectiveMatrix(double fovY, double aspect, double nearPlane, double farPlane);
// Eye -> clip, orthographic box [l, r] x [b, t] x [-n, -f] in eye space.
Mat4 orthographicMatrix(double l, double r, double b, double t, double nearPlane, double farPlane);

// World -> clip of the sun's orthographic shadow camera, covering a sphere (centre, radius)
// of shadow casters and, below it, the ground down to z = groundZ (receivers further away
// along the light than the far plane would be wrongly lit). `sunDirection` points towards the
// sun. The box is snapped to whole shadow-map texels and its size to quarter octaves, so a
// slowly moving set of bodies does not make shadow edges shimmer from frame to frame.
struct ShadowProjection {
  Mat4 viewProjection = Mat4::Identity();
  double texelSize = 0;   // m, one shadow-map texel on a plane facing the sun
  double depthRange = 1;  // m, far minus near plane: converts a depth bias in m to [0, 1]
};
ShadowProjection fitShadowProjection(const Vec3& sunDirection, const Vec3& centre, double radius,
                                     double groundZ, int mapSize);

}  // namespace vf

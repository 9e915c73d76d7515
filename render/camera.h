// Camera and projection math for the renderer: plain Eigen, no GL, so it is unit-testable.
// Conventions: world is SI metres, z up; eye space looks down -z (OpenGL); clip-space depth
// is [-1, 1]; matrices act on column vectors.
#pragma once

#include <Eigen/Core>
#include <span>

#include "sim/core/math.h"
#include "sim/scene/drawing_spec.h"

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

// A keyframed camera path at time t (s): position, look-at point and field of view each follow
// a cubic Hermite curve through the keys with Catmull-Rom tangents (the chord through the two
// neighbouring keys, divided by their time difference; one-sided at the ends), so the camera
// passes through every key exactly, with a velocity continuous across keys. Before the first
// key and after the last it holds still there. `keys` must be non-empty, times increasing.
CameraView interpolateCameraPath(std::span<const CameraKey> keys, double t, const Vec3& up);

// One frame of a chase camera's lag: moves `current` towards `target` by the fraction
// 1 - exp(-dt / timeConstant) of the gap, the exact solution over dt of dc/dt = (target - c) / T
// for a target held still over the step. So a jump in the target decays as exp(-t / T) whatever
// the frame rate, and a target moving at constant velocity v is followed at a lag that tends
// to v dt a / (1 - a) with a = exp(-dt / T) (about v T). timeConstant 0: no lag.
Vec3 chaseStep(const Vec3& current, const Vec3& target, double dt, double timeConstant);

// Size in pixels, in an image `imageHeight` pixels high, of a segment 2 * radius (m) long at
// `centre`, facing `camera`: the diameter of a small sphere there (off the axis a wide lens
// stretches it a little further). Infinite at or behind the eye.
double projectedDiameter(const CameraView& camera, const Vec3& centre, double radius,
                         int imageHeight);

}  // namespace vf

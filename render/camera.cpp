#include "render/camera.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace vf {

Mat4 CameraView::viewMatrix() const { return lookAtMatrix(position, lookAt, up); }

Mat4 CameraView::projectionMatrix(double aspect) const {
  return perspectiveMatrix(fovYDegrees * std::numbers::pi / 180.0, aspect, nearPlane, farPlane);
}

Mat4 lookAtMatrix(const Vec3& eye, const Vec3& target, const Vec3& up) {
  Vec3 forward = target - eye;
  if (forward.norm() < 1e-12) forward = Vec3(0, 1, 0);
  forward.normalize();
  Vec3 side = forward.cross(up);
  if (side.norm() < 1e-6 * std::max(up.norm(), 1e-300)) {
    // Looking along `up`: any perpendicular axis gives a valid (if arbitrary) roll.
    side = forward.cross(std::abs(forward.y()) < 0.9 ? Vec3::UnitY() : Vec3::UnitX());
  }
  side.normalize();
  const Vec3 trueUp = side.cross(forward);
  Mat4 m = Mat4::Identity();
  m.block<1, 3>(0, 0) = side.transpose();
  m.block<1, 3>(1, 0) = trueUp.transpose();
  m.block<1, 3>(2, 0) = -forward.transpose();
  m(0, 3) = -side.dot(eye);
  m(1, 3) = -trueUp.dot(eye);
  m(2, 3) = forward.dot(eye);
  return m;
}

Mat4 perspectiveMatrix(double fovY, double aspect, double nearPlane, double farPlane) {
  const double f = 1.0 / std::tan(fovY / 2);
  Mat4 m = Mat4::Zero();
  m(0, 0) = f / aspect;
  m(1, 1) = f;
  m(2, 2) = (farPlane + nearPlane) / (nearPlane - farPlane);
  m(2, 3) = 2 * farPlane * nearPlane / (nearPlane - farPlane);
  m(3, 2) = -1;
  return m;
}

Mat4 orthographicMatrix(double l, double r, double b, double t, double nearPlane, double farPlane) {
  Mat4 m = Mat4::Identity();
  m(0, 0) = 2 / (r - l);
  m(1, 1) = 2 / (t - b);
  m(2, 2) = -2 / (farPlane - nearPlane);
  m(0, 3) = -(r + l) / (r - l);
  m(1, 3) = -(t + b) / (t - b);
  m(2, 3) = -(farPlane + nearPlane) / (farPlane - nearPlane);
  return m;
}

ShadowProjection fitShadowProjection(const Vec3& sunDirection, const Vec3& centre, double radius,
                                     double groundZ, int mapSize) {
  const Vec3 toSun = sunDirection.normalized();
  // Quarter-octave steps: the box only changes size when the casters' extent changes by 19%.
  radius = std::max(radius, 1e-3);
  const double r = std::exp2(std::ceil(std::log2(radius) * 4) / 4) * 1.02;
  // Orientation is fixed by the sun alone (up = z, or y when the sun is overhead), so the
  // light-space axes never rotate and snapping the centre to texels is meaningful.
  const Vec3 origin = Vec3::Zero();
  const Mat4 rotation = lookAtMatrix(origin, origin - toSun, Vec3::UnitZ());
  const double texel = 2 * r / mapSize;
  Vec4 c = rotation * Vec4(centre.x(), centre.y(), centre.z(), 1);
  c.x() = std::floor(c.x() / texel) * texel;
  c.y() = std::floor(c.y() / texel) * texel;
  // Depth: from r in front of the casters to the ground under them (along the light).
  double depthBehind = r;
  if (toSun.z() > 1e-3 && centre.z() > groundZ) {
    depthBehind = std::max(depthBehind, (centre.z() - groundZ) / toSun.z() + r);
  }
  // Eye space looks down -z: the casters' centre lies at depth -c.z().
  const double nearPlane = -c.z() - 2 * r;
  const double farPlane = -c.z() + depthBehind + r;
  ShadowProjection p;
  p.viewProjection =
      orthographicMatrix(c.x() - r, c.x() + r, c.y() - r, c.y() + r, nearPlane, farPlane) *
      rotation;
  p.texelSize = texel;
  p.depthRange = farPlane - nearPlane;
  return p;
}

namespace {

// Cubic Hermite on one segment: value at s in [0, 1] from the end values and the end slopes
// (per second) over a segment of h seconds. At s = 0 and s = 1 the basis is exactly (1, 0, 0, 0)
// and (0, 0, 1, 0), so the keys are hit bit for bit.
template <class T>
T hermite(const T& p0, const T& m0, const T& p1, const T& m1, double h, double s) {
  const double s2 = s * s, s3 = s2 * s;
  return (2 * s3 - 3 * s2 + 1) * p0 + (s3 - 2 * s2 + s) * h * m0 + (-2 * s3 + 3 * s2) * p1 +
         (s3 - s2) * h * m1;
}

// Catmull-Rom slope at key i of values v(key): the chord of its neighbours over their time gap.
template <class T, class Get>
T slopeAt(std::span<const CameraKey> keys, std::size_t i, Get get) {
  const std::size_t a = i > 0 ? i - 1 : i;
  const std::size_t b = i + 1 < keys.size() ? i + 1 : i;
  return (get(keys[b]) - get(keys[a])) / (keys[b].time - keys[a].time);
}

}  // namespace

CameraView interpolateCameraPath(std::span<const CameraKey> keys, double t, const Vec3& up) {
  CameraView view;
  view.up = up;
  const auto hold = [&](const CameraKey& k) {
    view.position = k.position;
    view.lookAt = k.lookAt;
    view.fovYDegrees = k.fovDegrees;
    return view;
  };
  if (keys.size() == 1 || t <= keys.front().time) return hold(keys.front());
  if (t >= keys.back().time) return hold(keys.back());
  // The segment [t_i, t_i+1) holding t.
  std::size_t i = 0;
  while (t >= keys[i + 1].time) ++i;
  const double h = keys[i + 1].time - keys[i].time;
  const double s = (t - keys[i].time) / h;
  const auto position = [](const CameraKey& k) { return k.position; };
  const auto lookAt = [](const CameraKey& k) { return k.lookAt; };
  const auto fov = [](const CameraKey& k) { return k.fovDegrees; };
  view.position = hermite<Vec3>(keys[i].position, slopeAt<Vec3>(keys, i, position),
                                keys[i + 1].position, slopeAt<Vec3>(keys, i + 1, position), h, s);
  view.lookAt = hermite<Vec3>(keys[i].lookAt, slopeAt<Vec3>(keys, i, lookAt), keys[i + 1].lookAt,
                              slopeAt<Vec3>(keys, i + 1, lookAt), h, s);
  view.fovYDegrees =
      hermite<double>(keys[i].fovDegrees, slopeAt<double>(keys, i, fov), keys[i + 1].fovDegrees,
                      slopeAt<double>(keys, i + 1, fov), h, s);
  return view;
}

Vec3 chaseStep(const Vec3& current, const Vec3& target, double dt, double timeConstant) {
  if (!(timeConstant > 0)) return target;
  return current + (target - current) * (1 - std::exp(-dt / timeConstant));
}

double projectedDiameter(const CameraView& camera, const Vec3& centre, double radius,
                         int imageHeight) {
  const Vec3 forward = (camera.lookAt - camera.position).normalized();
  const double depth = forward.dot(centre - camera.position);
  if (!(depth > 0)) return std::numeric_limits<double>::infinity();  // at or behind the eye
  const double halfHeight = depth * std::tan(camera.fovYDegrees * std::numbers::pi / 360);
  return radius / halfHeight * imageHeight;
}

}  // namespace vf

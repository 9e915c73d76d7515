#include "render/auto_framing.h"

#include <algorithm>
#include <numbers>
#include <vector>

namespace vf {
namespace {

constexpr double kDegrees = std::numbers::pi / 180;

}  // namespace

Sphere enclose(const Sphere& a, const Sphere& b) {
  const Vec3 d = b.centre - a.centre;
  const double dist = d.norm();
  if (dist + b.radius <= a.radius) return a;
  if (dist + a.radius <= b.radius) return b;
  const double radius = (dist + a.radius + b.radius) / 2;
  // dist > 0 here: equal centres are caught by one of the containment tests above.
  return Sphere{a.centre + d * ((radius - a.radius) / dist), radius};
}

Sphere encloseAll(std::span<const Sphere> spheres) {
  if (spheres.empty()) return Sphere{Vec3::Zero(), 1};
  Eigen::AlignedBox3d box;
  for (const Sphere& s : spheres) {
    box.extend(s.centre - Vec3::Constant(s.radius));
    box.extend(s.centre + Vec3::Constant(s.radius));
  }
  Sphere out{box.center(), 0};
  for (const Sphere& s : spheres) {
    out.radius = std::max(out.radius, (s.centre - out.centre).norm() + s.radius);
  }
  return out;
}

Vec3 defaultAutoView() { return Vec3(-4, 6, 0).normalized(); }

AutoFraming::AutoFraming(double fovYDegrees, double aspect, const Vec3& view, double pitchDegrees)
    : fovYDegrees_(fovYDegrees) {
  const Vec3 horizontal = Vec3(view.x(), view.y(), 0).normalized();
  const double pitch = pitchDegrees * kDegrees;
  forward_ = horizontal * std::cos(pitch) - Vec3::UnitZ() * std::sin(pitch);
  right_ = forward_.cross(Vec3::UnitZ()).normalized();
  up_ = right_.cross(forward_);
  halfY_ = fovYDegrees * kDegrees / 2;
  halfX_ = std::atan(std::tan(halfY_) * aspect);
  // Inward normals of the four side planes of a frustum with this orientation (any position).
  const double ca = std::cos(halfX_), sa = std::sin(halfX_);
  const double cb = std::cos(halfY_), sb = std::sin(halfY_);
  normals_ = {-ca * right_ + sa * forward_, ca * right_ + sa * forward_, -cb * up_ + sb * forward_,
              cb * up_ + sb * forward_};
}

void AutoFraming::add(const Sphere& s) {
  // A sphere is inside side plane j of a camera at P when n_j . (s - P) >= r, i.e.
  // n_j . P <= n_j . s - r: keep the tightest right-hand side per plane.
  for (std::size_t j = 0; j < 4; ++j) {
    const double h = normals_[j].dot(s.centre) - s.radius * kMargin;
    limits_[j] = empty_ ? h : std::min(limits_[j], h);
  }
  const Sphere grown{s.centre, s.radius};
  region_ = empty_ ? grown : enclose(region_, grown);
  empty_ = false;
}

CameraView AutoFraming::camera(double lowestEye) const {
  const Sphere region = empty_ ? Sphere{Vec3::Zero(), 1} : region_;
  std::array<double, 4> h = limits_;
  if (empty_) {
    for (std::size_t j = 0; j < 4; ++j) h[j] = normals_[j].dot(region.centre) - region.radius;
  }
  // Position P = x right + y up + z forward, as far forward as the four constraints
  // n_j . P <= h_j allow. The right/left pair bounds z by (hR + hL) / (2 sin a) and fixes x
  // midway, the top/bottom pair likewise; the tighter pair decides, the other is centred.
  const double x = (h[1] - h[0]) / (2 * std::cos(halfX_));
  const double y = (h[3] - h[2]) / (2 * std::cos(halfY_));
  const double z =
      std::min((h[0] + h[1]) / (2 * std::sin(halfX_)), (h[2] + h[3]) / (2 * std::sin(halfY_)));
  Vec3 position = x * right_ + y * up_ + z * forward_;
  if (position.z() < lowestEye) {
    // Up along the picture's up to that height, then back (which eases every side plane's
    // constraint, n_j . forward > 0) until everything is in view again: the view keeps its
    // pitch, and with it the horizon.
    position += up_ * ((lowestEye - position.z()) / up_.z());
    double back = 0;
    for (std::size_t j = 0; j < 4; ++j)
      back = std::max(back, (normals_[j].dot(position) - h[j]) / normals_[j].dot(forward_));
    position -= forward_ * back;
  }
  // A little air around the outermost bodies: step back by a tenth of the distance.
  const double distance = std::max(forward_.dot(region.centre - position), 1e-3);
  position -= forward_ * (0.1 * distance);
  CameraView c;
  c.position = position;
  c.lookAt = position + forward_ * (1.1 * distance);
  c.up = Vec3::UnitZ();
  c.fovYDegrees = fovYDegrees_;
  return c;
}

Sphere viewSlice(const CameraView& camera, double aspect, double depth) {
  const Vec3 forward = (camera.lookAt - camera.position).normalized();
  const Mat4 view = camera.viewMatrix();
  const Vec3 right = view.block<1, 3>(0, 0).transpose();
  const Vec3 up = view.block<1, 3>(1, 0).transpose();
  const double h = depth * std::tan(camera.fovYDegrees * kDegrees / 2), w = h * aspect;
  std::vector<Sphere> corners{Sphere{camera.position, 0}};
  for (const double sx : {-1.0, 1.0}) {
    for (const double sy : {-1.0, 1.0}) {
      corners.push_back(
          Sphere{camera.position + forward * depth + right * (sx * w) + up * (sy * h), 0});
    }
  }
  return encloseAll(corners);
}

}  // namespace vf

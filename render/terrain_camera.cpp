#include "render/terrain_camera.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace vf {

std::optional<Vec3> downhillNear(const Heightfield& h, std::span<const Vec3> points,
                                 double margin) {
  if (points.empty()) return std::nullopt;
  Eigen::AlignedBox2d box;
  for (const Vec3& p : points) box.extend(p.head<2>());
  const auto index = [&](double v, double origin, int n) {
    return std::clamp(static_cast<int>(std::floor((v - origin) / h.cell)), 0, n - 1);
  };
  const int i0 = index(box.min().x() - margin, h.x0, h.nx);
  const int i1 = index(box.max().x() + margin + h.cell, h.x0, h.nx);
  const int j0 = index(box.min().y() - margin, h.y0, h.ny);
  const int j1 = index(box.max().y() + margin + h.cell, h.y0, h.ny);
  // Normal equations of z = a x + b y + c in coordinates about the box's first sample (their
  // sums stay small, so the solve is well conditioned).
  Eigen::Matrix3d ata = Eigen::Matrix3d::Zero();
  Eigen::Vector3d atz = Eigen::Vector3d::Zero();
  int count = 0;
  for (int j = j0; j <= j1; ++j) {
    for (int i = i0; i <= i1; ++i) {
      const double z = h.at(i, j);
      if (std::isnan(z)) continue;
      const Eigen::Vector3d row((i - i0) * h.cell, (j - j0) * h.cell, 1);
      ata += row * row.transpose();
      atz += row * z;
      ++count;
    }
  }
  if (count < 3) return std::nullopt;
  const Eigen::Vector3d abc = ata.ldlt().solve(atz);
  const Vec3 down(-abc.x(), -abc.y(), 0);
  if (!(down.norm() > 1e-3)) return std::nullopt;
  return Vec3(down.normalized());
}

Vec3 acrossSlope(const Vec3& downhill, double upDegrees) {
  const double a = upDegrees * std::numbers::pi / 180;
  const Vec3 across = Vec3::UnitZ().cross(downhill).normalized();
  return (across * std::cos(a) - downhill.normalized() * std::sin(a)).normalized();
}

void keepAboveTerrain(const Heightfield& h, CameraView& camera, const Vec3& target,
                      double clearance) {
  double z = camera.position.z();
  const double under = h.heightAt(camera.position.x(), camera.position.y());
  if (!std::isnan(under)) z = std::max(z, under + clearance);
  // The sight line p(t) = eye (1 - t) + target t keeps above ground g(t) + clearance (1 - t)
  // when the eye's height is at least (g(t) - target.z t) / (1 - t) + clearance.
  const double length = (target - camera.position).head<2>().norm();
  const int samples = std::clamp(static_cast<int>(2 * length / h.cell), 1, 256);
  for (int k = 1; k <= samples; ++k) {
    const double t = 0.95 * k / samples;
    const Vec3 p = camera.position * (1 - t) + target * t;
    const double ground = h.heightAt(p.x(), p.y());
    if (!std::isnan(ground)) z = std::max(z, (ground - target.z() * t) / (1 - t) + clearance);
  }
  camera.position.z() = z;
}

}  // namespace vf

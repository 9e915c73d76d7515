// Rock volumes and resized shapes (see block_size.h).
#include "sim/ensemble/block_size.h"

#include <algorithm>
#include <cmath>

#include "sim/core/error.h"
#include "sim/shape/shape.h"

namespace vf {
namespace {

double normalCdf(double z) { return 0.5 * std::erfc(-z / std::sqrt(2.0)); }

// The standard normal quantile of p in (Phi(lo), Phi(hi)), by bisection on [lo, hi]: 200 halvings
// reach the spacing of doubles, and bisection gives the same bits wherever it runs.
double normalQuantile(double p, double lo, double hi) {
  for (int k = 0; k < 200 && lo < hi; ++k) {
    const double mid = 0.5 * (lo + hi);
    if (mid <= lo || mid >= hi) break;
    (normalCdf(mid) < p ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

}  // namespace

double volumeAt(const VolumeSpec& v, double u) {
  if (v.law == VolumeSpec::Law::kPower) {
    // P(X > V) = (V^-b - max^-b) / (min^-b - max^-b) on [min, max]; solved for V at 1 - u.
    const double b = v.exponent;
    const double a = std::pow(v.min, -b), c = std::pow(v.max, -b);
    return std::clamp(std::pow(c + (1 - u) * (a - c), -1 / b), v.min, v.max);
  }
  const double mu = std::log(v.median);
  const double zLo = (std::log(v.min) - mu) / v.sigma, zHi = (std::log(v.max) - mu) / v.sigma;
  const double p = normalCdf(zLo) + u * (normalCdf(zHi) - normalCdf(zLo));
  return std::clamp(std::exp(mu + v.sigma * normalQuantile(p, zLo, zHi)), v.min, v.max);
}

std::shared_ptr<const Shape> resizedShape(const Shape& base, double volume, double density) {
  VF_ASSERT(volume > 0 && density > 0 && base.volume > 0);
  const double s = std::cbrt(volume / base.volume);
  auto tree = std::make_shared<SphereTree>();
  tree->levels = base.tree->levels;
  for (SphereTreeLevel& level : tree->levels) {
    level.edge *= s;
    level.radius *= s;
    for (Vec3& c : level.centers) c *= s;
  }
  finishSphereTree(*tree);
  // Back to the mesh file's coordinates, so that makeShape scales about the file's origin and
  // the scaled shape's meshOrigin is the base's times s.
  TriMesh fileMesh = base.mesh;
  fileMesh.translate(-base.meshOrigin);
  return makeShape(base.name, std::move(fileMesh), Vec3::Constant(s), density,
                   base.tree->leafLevel(), std::move(tree));
}

}  // namespace vf

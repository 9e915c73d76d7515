// Vector and matrix types used throughout voxfall. SI units, z up.
// Eigen is the math library of the whole project, so unlike assimp, GL, png and
// libav it may appear in voxfall headers.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace vf {

using Vec2 = Eigen::Vector2d;  // plan-view points (x, y), e.g. map outlines
using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;
using Quat = Eigen::Quaterniond;  // stored (x, y, z, w); constructed Quat(w, x, y, z)

}  // namespace vf

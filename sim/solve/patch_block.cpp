// The patch block's pseudo-inverse (patch_block.h), apart from the solver that uses it.
#include "sim/solve/patch_block.h"

#include <Eigen/Eigenvalues>
#include <cmath>

namespace vf {

bool patchBlockInverse(const Eigen::Matrix4d& block, int m, const Vec3* arms, const Vec3& n,
                       Eigen::Matrix4d& inverse) {
  // Rows and columns beyond m: K(0, 0) on the diagonal, the block's own scale, so that the
  // cut-offs below are relative to the block whatever the bodies' masses (never read).
  Eigen::Matrix4d K = Eigen::Matrix4d::Zero();
  K.topLeftCorner(m, m) = block.topLeftCorner(m, m);
  for (int i = m; i < 4; ++i) K(i, i) = K(0, 0);
  // The closed form. K_ij = 1/M_a + 1/M_b + (r_ai x n).I_a^-1 (r_aj x n) + (r_bi x n).I_b^-1
  // (r_bj x n), and r_bi = r_ai + x_a - x_b, so K u = 0 for every u with sum u_i = 0 and
  // sum u_i (r_ai x n) = 0: the affine dependencies of the points seen along n. Four points in
  // a plane have one, u_k = n.(d_l x d_m) for (k, l, m) cyclic in (1, 2, 3), d_k = arm_k -
  // arm_0, u_0 = -(u_1 + u_2 + u_3) (Cramer's rule in the plane); fewer generally have none.
  // With K's null vector u (unit) known, K + s u u^T is invertible and its inverse is
  // K^+ + u u^T / s, for any s > 0 (K is symmetric: u is orthogonal to K's range).
  Eigen::Vector4d u = Eigen::Vector4d::Zero();
  const double s = K.trace() / 4;
  bool closed = std::isfinite(s) && s > 0;
  if (closed && m == 4) {
    const Vec3 d1 = arms[1] - arms[0], d2 = arms[2] - arms[0], d3 = arms[3] - arms[0];
    u << 0, n.dot(d2.cross(d3)), n.dot(d3.cross(d1)), n.dot(d1.cross(d2));
    u[0] = -(u[1] + u[2] + u[3]);
    // All four points nearly on one line: u is rounding (and K has a second null direction).
    const double spread = d1.squaredNorm() + d2.squaredNorm() + d3.squaredNorm();
    const double uu = u.squaredNorm();
    closed = uu > 1e-12 * spread * spread;
    if (closed) u /= std::sqrt(uu);
  }
  const Eigen::Matrix4d lifted = K + s * u * u.transpose();  // K itself where u = 0
  // Taken only where every eigenvalue of the lifted K (K's non-zero ones, s for u, K(0, 0) for
  // the padding) lies above 1e-6 of the largest, far from the eigen-decomposition's cut-off of
  // 1e-9: then both give K^+ up to rounding. It is positive semidefinite, so lambda_min >= det /
  // lambda_max^3 >= det / trace^3, and det >= 1e-6 trace^4 suffices.
  if (closed) {
    const double trace = lifted.trace();
    closed = lifted.determinant() >= 1e-6 * trace * trace * trace * trace;
  }
  if (closed) {
    inverse = lifted.inverse();
    if (m == 4) inverse -= (u / s) * u.transpose();
    return true;
  }
  // Otherwise the eigen-decomposition: directions K does not move (up to rounding of its
  // entries) are left out.
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix4d> eigen(K);
  const Eigen::Vector4d lambda = eigen.eigenvalues();
  const double floor = 1e-9 * lambda.cwiseAbs().maxCoeff();
  Eigen::Vector4d inv;
  for (int i = 0; i < 4; ++i) inv[i] = lambda[i] > floor ? 1.0 / lambda[i] : 0.0;
  inverse = eigen.eigenvectors() * inv.asDiagonal() * eigen.eigenvectors().transpose();
  return false;
}

}  // namespace vf

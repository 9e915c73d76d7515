// Mass properties against closed forms: boxes (centred, off-centre, rotated and translated),
// an octahedron, an L-shape (parallel-axis theorem by hand) and an icosphere (bounded by the
// inscribed and circumscribed balls).
#include "sim/geometry/mass_properties.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "tests/sim/test_meshes.h"

namespace vf {
namespace {

// Every result below is a sum of at most a few thousand terms each of the size of the result
// (reference point at the box centre): relative round-off ~1e-14, so 1e-12 leaves margin
// while any formula error (a wrong 1/60 vs 1/120, a missing parallel-axis term) is O(1).
constexpr double kRel = 1e-12;

Mat3 boxInertia(double m, double a, double b, double c) {
  return Mat3(Eigen::Vector3d(b * b + c * c, a * a + c * c, a * a + b * b).asDiagonal()) * m / 12;
}

void expectMatNear(const Mat3& got, const Mat3& want, double tol) {
  EXPECT_LE((got - want).cwiseAbs().maxCoeff(), tol) << "got\n" << got << "\nwant\n" << want;
}

TEST(MassProperties, CentredBox) {
  const double a = 2, b = 3, c = 5, rho = 7;
  const auto mp =
      computeMassProperties(test::boxMesh(Vec3(-1, -1.5, -2.5), Vec3(1, 1.5, 2.5)), rho);
  const double m = rho * a * b * c;
  EXPECT_NEAR(mp.volume, a * b * c, kRel * a * b * c);
  EXPECT_NEAR(mp.mass, m, kRel * m);
  EXPECT_LE(mp.centerOfMass.norm(), kRel * 5);
  expectMatNear(mp.inertia, boxInertia(m, a, b, c), kRel * m * 25);
}

TEST(MassProperties, OffCentreBoxCentreOfMass) {
  const auto mp = computeMassProperties(test::boxMesh(Vec3(1, 2, -5), Vec3(3, 3, -1)), 1.0);
  EXPECT_NEAR(mp.volume, 8, kRel * 8);
  EXPECT_LE((mp.centerOfMass - Vec3(2, 2.5, -3)).norm(), kRel * 5);
  // Inertia is about the COM: the same as the centred box of the same size.
  expectMatNear(mp.inertia, boxInertia(8, 2, 1, 4), kRel * 8 * 16);
}

TEST(MassProperties, FarFromOriginKeepsPrecision) {
  // A unit cube 1e6 m from the origin. With the origin as reference the tetra terms would be
  // ~1e12 and cancel to ~1: about 1e-4 absolute error in the inertia. With the bounding-box
  // centre as reference only the coordinate rounding (~1e-10 at 1e6) remains.
  const Vec3 lo(1e6, -2e6, 3e6);
  const auto mp = computeMassProperties(test::boxMesh(lo, lo + Vec3(1, 1, 1)), 1.0);
  EXPECT_NEAR(mp.volume, 1, 1e-8);
  EXPECT_LE((mp.centerOfMass - (lo + Vec3::Constant(0.5))).norm(), 1e-8);
  expectMatNear(mp.inertia, boxInertia(1, 1, 1, 1), 1e-8);
}

TEST(MassProperties, RotatedTranslatedBoxTransformsAsRIRt) {
  const double a = 1, b = 2, c = 4, rho = 3;
  TriMesh m = test::boxMesh(Vec3(-a / 2, -b / 2, -c / 2), Vec3(a / 2, b / 2, c / 2));
  const Mat3 R = Eigen::AngleAxisd(0.7, Vec3(1, 2, 3).normalized()).toRotationMatrix();
  const Vec3 t(0.3, -2, 5);
  for (Vec3& v : m.vertices) v = R * v + t;
  const auto mp = computeMassProperties(m, rho);
  const double mass = rho * a * b * c;
  EXPECT_NEAR(mp.mass, mass, kRel * mass);
  EXPECT_LE((mp.centerOfMass - t).norm(), kRel * 10);
  expectMatNear(mp.inertia, R * boxInertia(mass, a, b, c) * R.transpose(), kRel * mass * 20);
  // Symmetric by construction.
  EXPECT_EQ(mp.inertia, mp.inertia.transpose());
}

TEST(MassProperties, Octahedron) {
  // |x| + |y| + |z| <= 1: volume 4/3; int x^2 dV = int_{-1}^{1} x^2 * 2 (1 - |x|)^2 dx = 2/15
  // (the cross-section at x is a square of diagonal 2 (1 - |x|)), so I_xx = rho * 4/15.
  TriMesh m;
  for (int k = 0; k < 3; ++k) {
    m.vertices.push_back(Vec3::Unit(k));
    m.vertices.push_back(-Vec3::Unit(k));
  }
  for (int sx = 0; sx < 2; ++sx)
    for (int sy = 0; sy < 2; ++sy)
      for (int sz = 0; sz < 2; ++sz) {
        std::array<std::uint32_t, 3> t{std::uint32_t(sx), std::uint32_t(2 + sy),
                                       std::uint32_t(4 + sz)};
        if ((sx + sy + sz) % 2 == 1) std::swap(t[1], t[2]);  // odd reflections reverse winding
        m.triangles.push_back(t);
      }
  const double rho = 2;
  const auto mp = computeMassProperties(m, rho);
  EXPECT_NEAR(mp.volume, 4.0 / 3, kRel);
  EXPECT_LE(mp.centerOfMass.norm(), kRel);
  expectMatNear(mp.inertia, Mat3::Identity() * rho * 4 / 15, kRel);
}

TEST(MassProperties, LShapeByParallelAxisTheorem) {
  // L = A u B, A = [0,2]x[0,1]x[0,h], B = [0,1]x[1,3]x[0,h], as one closed prism.
  const double h = 0.5, rho = 10;
  const TriMesh m = test::extrudedPolygon({{1, 1}, {1, 3}, {0, 3}, {0, 0}, {2, 0}, {2, 1}}, 0,
                                          h);  // fan from the reflex corner
  const double mA = rho * 2 * 1 * h, mB = rho * 1 * 2 * h;
  const Vec3 gA(1, 0.5, h / 2), gB(0.5, 2, h / 2);
  const Vec3 g = (mA * gA + mB * gB) / (mA + mB);
  // Parallel-axis (Steiner): I_about_g = I_own + m (|d|^2 Id - d d^T), d = own COM - g.
  auto steiner = [&](double mass, const Vec3& d) {
    return Mat3(mass * (d.squaredNorm() * Mat3::Identity() - d * d.transpose()));
  };
  const Mat3 want =
      boxInertia(mA, 2, 1, h) + steiner(mA, gA - g) + boxInertia(mB, 1, 2, h) + steiner(mB, gB - g);

  const auto mp = computeMassProperties(m, rho);
  EXPECT_NEAR(mp.mass, mA + mB, kRel * (mA + mB));
  EXPECT_LE((mp.centerOfMass - g).norm(), kRel * 3);
  expectMatNear(mp.inertia, want, kRel * want.norm());
  EXPECT_NE(mp.inertia(0, 1), 0.0);  // the L has a real product of inertia: not a box
}

TEST(MassProperties, IcosphereBetweenInscribedAndCircumscribedBalls) {
  // Every vertex is on the sphere of radius R, so the convex polyhedron lies inside the ball
  // of radius R and contains the ball of radius r_in = its smallest face-plane distance.
  // Volume and each diagonal inertia entry integrate a non-negative function over the solid,
  // so they are bracketed by the two balls' closed forms 4/3 pi r^3 and 8/15 pi rho r^5.
  const double R = 1.5, rho = 2;
  const TriMesh m = test::icosphere(3, R);  // 1280 triangles
  double rIn = R;
  for (const auto& t : m.triangles) {
    const Vec3 &a = m.vertices[t[0]], &b = m.vertices[t[1]], &c = m.vertices[t[2]];
    rIn = std::min(rIn, std::abs((b - a).cross(c - a).normalized().dot(a)));
  }
  ASSERT_GT(rIn, 0.99 * R);  // the bracket is tight enough to catch a wrong formula
  const double pi = std::numbers::pi;
  const auto mp = computeMassProperties(m, rho);
  EXPECT_GT(mp.volume, 4.0 / 3 * pi * std::pow(rIn, 3));
  EXPECT_LT(mp.volume, 4.0 / 3 * pi * std::pow(R, 3));
  for (int k = 0; k < 3; ++k) {
    EXPECT_GT(mp.inertia(k, k), 8.0 / 15 * pi * rho * std::pow(rIn, 5));
    EXPECT_LT(mp.inertia(k, k), 8.0 / 15 * pi * rho * std::pow(R, 5));
  }
  // The icosahedral symmetry group fixes no direction: the inertia is isotropic and the COM
  // is the centre, up to round-off.
  EXPECT_LE(mp.centerOfMass.norm(), kRel * R);
  expectMatNear(mp.inertia, Mat3::Identity() * mp.inertia.trace() / 3, kRel * mp.inertia.norm());
}

TEST(MassProperties, DensityScalesMassAndInertiaOnly) {
  const TriMesh m = test::extrudedPolygon({{1, 1}, {1, 3}, {0, 3}, {0, 0}, {2, 0}, {2, 1}}, 0, 1);
  const auto one = computeMassProperties(m, 1.0), many = computeMassProperties(m, 2500.0);
  EXPECT_EQ(one.centerOfMass, many.centerOfMass);  // bit-identical: centredMesh relies on it
  EXPECT_EQ(one.volume, many.volume);
  EXPECT_NEAR(many.mass, 2500 * one.mass, kRel * many.mass);
  expectMatNear(many.inertia, 2500 * one.inertia, kRel * many.inertia.norm());
}

}  // namespace
}  // namespace vf

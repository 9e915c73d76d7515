// The soft-soil scar layer over the slip law (Lu et al. 2019; sim/solve/scar_drag.cpp) against
// closed forms and independent computations: eq. 11's depth, the immersed frontal area of the
// equivalent ellipsoid against a brute-force shadow, a block sliding in the layer slowing as
// dv/dt = -k v^2 predicts, the layer left on a rebound, and a scar material that a body does
// not touch changing nothing. Each tolerance is derived in the comment beside it.
#include "sim/solve/scar_drag.h"

#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <numbers>

#include "sim/ground/ground_material.h"
#include "sim/world.h"
#include "tests/support/test_world.h"

namespace vf {
namespace {

constexpr double kG = 9.81;

// A frictionless slip material (mu(s) = 0) of normal restitution eps with Lu et al.'s scar layer:
// rho 1700 kg/m^3, C_f 1.0, C_s 1.5, M_e 15 MN/m^2.
GroundMaterial scarMaterial(double eps) {
  GroundMaterial m;
  m.name = "scar";
  m.law = GroundLawKind::kSlip;
  m.restitution = eps;
  m.scar = true;
  m.scarDensity = 1700;
  m.scarFluidDrag = 1.0;
  m.scarCompactionDrag = 1.5;
  m.scarModulus = 15;
  return m;
}

std::shared_ptr<const GroundMap> oneMaterial(const GroundMaterial& m) {
  auto g = std::make_shared<GroundMap>();
  g->materials.push_back(m);
  return g;
}

// The semi-axis of the box's equivalent ellipsoid along an edge of length L: a box's second
// moment of mass along an axis is m L^2 / 12, a solid ellipsoid's m a^2 / 5.
double equivalentSemiAxis(double L) { return L * std::sqrt(5.0 / 12.0); }

}  // namespace

// Eq. 11 with Lu et al.'s units (M kg, M_e kN/m^2, V m/s): for their 780 kg block on
// M_e = 25 MN/m^2 striking at 10 m/s, 0.1 * 780^(1/3) * 25000^(-0.4) * 10^0.8 = 0.1011243 m
// (computed by hand, outside voxfall), the order of their measured scars (0.13-0.21 m). With
// M_e in MN/m^2 in the formula the depth would be 1000^0.4 = 15.8 times that. The power laws:
// doubling M, M_e or V scales d by 2^(1/3), 2^(-0.4), 2^0.8. Rounding of pow and cbrt: 1e-12.
TEST(ScarDrag, Eq11DepthInLuEtAlsUnits) {
  EXPECT_NEAR(scarDepth(780, 25, 10), 0.10112430055710614, 1e-12);
  const double d = scarDepth(70, 15, 2);
  EXPECT_NEAR(scarDepth(140, 15, 2) / d, std::cbrt(2.0), 1e-12);
  EXPECT_NEAR(scarDepth(70, 30, 2) / d, std::pow(2.0, -0.4), 1e-12);
  EXPECT_NEAR(scarDepth(70, 15, 4) / d, std::pow(2.0, 0.8), 1e-12);
  EXPECT_EQ(scarDepth(70, 15, 0), 0.0);
}

// The unit circle's segment of height h: half the disc at h = 1, all of it at h = 2, and
// (4/3) sqrt(2 h) h (1 - h/10 + ...) for small h (its series: the next term is -h/10 of it, so
// at h = 1e-4 the relative error of the leading term is 1e-5).
TEST(ScarDrag, UnitSegmentArea) {
  EXPECT_NEAR(unitSegmentArea(1.0), std::numbers::pi / 2, 1e-15);
  EXPECT_NEAR(unitSegmentArea(2.0), std::numbers::pi, 1e-15);
  EXPECT_EQ(unitSegmentArea(0.0), 0.0);
  const double h = 1e-4;
  EXPECT_NEAR(unitSegmentArea(h) / (4.0 / 3.0 * std::sqrt(2 * h) * h), 1.0, 2e-5);
}

// The frontal area of a box's equivalent ellipsoid immersed to depth d, turned arbitrarily,
// against its shadow computed directly: a point p = h n + w u of the plane normal to the motion t
// (n the ground normal, u = n x t; about the centre) is in the shadow when h is within d of the
// lowest point (p.n is constant along t, since t is normal to n) and the line p + tau t meets
// the ellipsoid x^T Q x <= 1, Q = S^-1, S = R diag(a^2) R^T from the box's edge lengths (not
// from the shape's inertia, which the code uses): min over tau is p^T M p <= 1,
// M = Q - Q t t^T Q / (t^T Q t), a quadratic in w whose roots bound the shadow's width W(h).
// The shadow is convex, so W is concave on [lowest, lowest + d]: the trapezoid rule
// underestimates its integral and the midpoint rule overestimates it, and the two bracket the
// area (to rounding, 1e-15 of it).
TEST(ScarDrag, ImmersedAreaOfTheEquivalentEllipsoidMatchesItsShadow) {
  const double Lx = 0.6, Ly = 0.3, Lz = 0.15;
  auto shape = test::boxShape(Lx, Ly, Lz, 2600, 3);
  BodyInfo b;
  b.shape = shape;
  b.invMass = 1.0 / shape->mass;
  BodyState y;
  y.q = Quat(Eigen::AngleAxisd(0.7, Vec3(1, 2, 3).normalized()));
  const Mat3 R = y.q.toRotationMatrix();
  const Vec3 a(equivalentSemiAxis(Lx), equivalentSemiAxis(Ly), equivalentSemiAxis(Lz));
  const Mat3 Q = R * a.cwiseInverse().cwiseAbs2().asDiagonal() * R.transpose();
  const Mat3 S = R * a.cwiseAbs2().asDiagonal() * R.transpose();
  const Vec3 n = Vec3(0.2, -0.1, 1).normalized();
  const Vec3 t = n.cross(Vec3(1, 0.3, 0)).normalized();
  const Vec3 u = n.cross(t);
  const Mat3 M = Q - (Q * t) * (Q * t).transpose() / t.dot(Q * t);
  auto width = [&](double h) {
    const double a2 = u.dot(M * u), a1 = 2 * h * n.dot(M * u), a0 = h * h * n.dot(M * n);
    const double disc = a1 * a1 - 4 * a2 * (a0 - 1);
    return disc > 0 ? std::sqrt(disc) / a2 : 0.0;
  };
  const double lowest = -std::sqrt(n.dot(S * n));
  for (double d : {0.005, 0.03, 0.1, 0.3}) {
    const int cells = 4000;
    const double c = d / cells;
    double trapezoid = 0, midpoint = 0;
    for (int i = 0; i < cells; ++i) {
      const double h0 = lowest + i * c;
      trapezoid += 0.5 * c * (width(h0) + width(h0 + c));
      midpoint += c * width(h0 + 0.5 * c);
    }
    const double area = immersedFrontalArea(b, y, n, t, d);
    EXPECT_GE(area, trapezoid * (1 - 1e-12)) << "d = " << d;
    EXPECT_LE(area, midpoint * (1 + 1e-12)) << "d = " << d;
    EXPECT_LT(midpoint - trapezoid, 1e-3 * midpoint) << "d = " << d;  // a bracket that means it
  }
}

// A flat block (0.4 x 0.4 x 0.1 m) dropped 0.5 m onto frictionless ground with the scar layer
// while moving at 3 m/s. Its landing sets the scar depth to eq. 11 for its impact speed; from
// then on only the drag acts along the ground, and its speed follows the closed-form solution
// of dv/dt = -k v^2, v(t) = vL / (1 + k vL (t - tL)), k = 1/2 (C_f + C_s) rho A / m, A the
// segment of depth d of the equivalent ellipsoid's cross-section across the motion (an ellipse
// of semi-axes a_y, a_z: a_y a_z seg(d / a_z)), computed here from the box's edges. Each step
// applies the exact solution over its dt, so steps compose to the closed form; what separates
// them is rounding (1e-15 relative per step, 2000 steps) and the normal velocity the solver
// leaves in the contacts (eps_N = 0: its target is 0, met to 1e-12 m/s, so |v| differs from v_x
// by under 1e-12): 1e-10 m/s covers both. Without the drag v would stay 3 m/s; with the
// sphere's segment instead of the ellipse's, or with the depth of a 1000 times stiffer soil,
// v(tL + 2 s) would differ by over 0.01 m/s.
TEST(ScarDrag, ABlockSlidingInTheLayerSlowsAsTheDragOdePredicts) {
  const double h = 0.5, vx = 3.0, dt = 1e-3;
  const GroundMaterial m = scarMaterial(0.0);
  WorldDef def;
  def.groundHeight = 0.0;
  def.step = StepRule::fixed(dt);
  def.solverIterations = 1000;
  test::RockFallWorld rock(def, test::groundLaws(oneMaterial(m)));
  World& world = rock.world;
  auto s = test::boxShape(0.4, 0.4, 0.1, 800, 4);
  BodyDef bd;
  bd.shape = s;
  bd.position = Vec3(0, 0, test::restOffset(*s) + h);
  bd.velocity = Vec3(vx, 0, 0);
  world.addBody(bd);
  double vImpact = 0;
  while (world.time() < 1.0) {
    const double before = world.velocity(0).z();
    world.step(dt);
    if (world.velocity(0).z() > before + kG * dt) {  // an impulse pushed it up: the landing
      vImpact = -(before - kG * dt);                 // with this step's gravity
      break;
    }
  }
  ASSERT_GT(vImpact, 0.9 * std::sqrt(2 * kG * h));
  const double d = scarDepth(s->mass, m.scarModulus, vImpact);
  EXPECT_NEAR(rock.rockFall.scarDepth(0), d, 1e-15);
  const double ay = equivalentSemiAxis(0.4), az = equivalentSemiAxis(0.1);
  // The ellipse's segment: the circle of radius a_z's segment of height d, stretched by a_y / a_z.
  const double A =
      ay / az * (az * az * std::acos((az - d) / az) - (az - d) * std::sqrt(2 * az * d - d * d));
  const double k = 0.5 * (m.scarFluidDrag + m.scarCompactionDrag) * m.scarDensity * A / s->mass;
  const double tL = world.time(), vL = world.velocity(0).x();
  EXPECT_LT(vL, vx);
  for (int i = 1; i <= 4; ++i) {
    world.advanceTo(tL + 0.5 * i);
    const double t = world.time() - tL;
    EXPECT_NEAR(world.velocity(0).x(), vL / (1 + k * vL * t), 1e-10) << "t = " << t;
    EXPECT_NEAR(rock.rockFall.scarDepth(0), d, 1e-15);
  }
  EXPECT_LT(world.velocity(0).x(), vL - 0.3);  // the drag did slow it (k vL t is about 0.3)
}

// A rebound leaves the layer: with eps_N = 0.6 the block bounces off, and in flight, with no
// contact on scar ground, its scar depth is 0 and no drag acts (v_x constant to rounding).
TEST(ScarDrag, ARockThatReboundsLeavesTheLayer) {
  const double dt = 1e-3;
  WorldDef def;
  def.groundHeight = 0.0;
  def.step = StepRule::fixed(dt);
  test::RockFallWorld rock(def, test::groundLaws(oneMaterial(scarMaterial(0.6))));
  World& world = rock.world;
  auto s = test::boxShape(0.4, 0.4, 0.1, 800, 4);
  BodyDef bd;
  bd.shape = s;
  bd.position = Vec3(0, 0, test::restOffset(*s) + 0.5);
  bd.velocity = Vec3(3.0, 0, 0);
  world.addBody(bd);
  bool scarred = false, rebounded = false;
  while (world.time() < 1.0 && !rebounded) {
    world.step(dt);
    scarred = scarred || rock.rockFall.scarDepth(0) > 0;
    rebounded = scarred && rock.rockFall.scarDepth(0) == 0 && world.velocity(0).z() > 0;
  }
  ASSERT_TRUE(rebounded);
  const double vx = world.velocity(0).x();
  for (int i = 0; i < 50; ++i) {  // 0.05 s of the 0.3 s flight
    world.step(dt);
    EXPECT_EQ(rock.rockFall.scarDepth(0), 0.0);
  }
  EXPECT_NEAR(world.velocity(0).x(), vx, 1e-12);
}

// Off means off: a body sliding on slip ground takes the same bits whether or not a scar
// material lies elsewhere on the map (a class raster with the scar layer on x > 20 m only, which
// the body never reaches), so ScarDrag runs and changes nothing for bodies off scar ground.
TEST(ScarDrag, AScarMaterialABodyNeverTouchesChangesNoBit) {
  auto terrain =
      std::make_shared<const Heightfield>(test::flatHeightfield(41, 11, 1.0, 0.0, -5.0, -5.0));
  auto classes = std::make_shared<Heightfield>(*terrain);
  for (int j = 0; j < classes->ny; ++j)
    for (int i = 0; i < classes->nx; ++i)
      classes->z[static_cast<std::size_t>(j) * classes->nx + i] = classes->x0 + i > 20 ? 1 : 0;
  const GroundMaterial slip = *groundPreset("ramms_chant_sura", 0.8);
  auto run = [&](bool scarElsewhere) {
    auto g = std::make_shared<GroundMap>();
    g->materials = {slip};
    if (scarElsewhere) {
      g->materials.push_back(*groundPreset("ramms_chant_sura_scar", 0.8));
      g->materialOfClass = {0, 1};
      g->classes = classes;
      EXPECT_TRUE(g->hasScar());
    }
    WorldDef def;
    def.terrain = terrain;
    test::RockFallWorld rock(def, test::groundLaws(g));
    World& world = rock.world;
    auto s = test::boxShape(0.4, 0.3, 0.2, 2600, 3);
    BodyDef bd;
    bd.shape = s;
    bd.position = Vec3(-2, 0, 0.6);
    bd.velocity = Vec3(3.0, 0.2, 0);
    bd.angularVelocity = Vec3(1, 2, 0);
    world.addBody(bd);
    world.advanceTo(2.0);
    EXPECT_LT(world.state(0).x.x(), 14.0);
    return world.stepsHash();
  };
  EXPECT_EQ(run(true), run(false));
}

}  // namespace vf

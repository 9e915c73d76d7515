// Creep: on a plane inclined at theta = 15 degrees, a rock under STONE's law with rolling
// resistance mu_r = tan(theta) rolls on at its speed for ever (the brake and gravity balance),
// while a cube under the slip law (eps_N = 0, mu large enough that it cannot slide) stops within
// a distance and a time derived below from its corner impacts. The incline is a terrain, since
// the rest criterion and the outcomes are kept for terrain only.
//
// The cube (edge a = 0.4 m, level 4) rolls in the x-z plane over the edges of its sphere tree's
// cross-section: a square of leaf centres with half-side h = a/2 - e/2 (e = a/16 the leaf
// voxel's edge), rounded by the leaf radius rho = e sqrt(3)/2: h = 0.1875 m, rho = 0.02165 m.
// Per unit mass (E: kinetic energy, I: moment of inertia; I_G = a^2/6 = 0.02667 m^2 about the
// rolling axis):
//  - Impact (eps_N = 0, no slip, plastic on the next edge): angular momentum about the new
//    contact point is kept, omega+ / omega- = (I_G + r_old . r_new) / (I_G + |r_new|^2) with
//    r_old = (h, h + rho), r_new = (-h, h + rho) from the contact points to the centre of mass:
//    r = 0.3340 (1/4 for a sharp cube), and E+ = r^2 E- = 0.1115 E-. The rolling moments
//    before and after are equal, so E scales by r^2.
//  - Between impacts the centre of mass advances by a roll length 2h + rho pi/2 = 0.4090 m, so
//    E gains G = g sin(theta) (2h + rho pi/2) = 1.0385 J/kg.
//  - Tipping over the edge at angle psi (0 flat on the face, pi/2 on the next) lifts the centre
//    by dU(psi) = g [cos(theta) c (cos(45deg - psi) - cos 45deg) + sin(theta) (c sin(45deg - psi)
//    - c sin 45deg - rho psi)], c = h sqrt(2); its slope, the restoring torque, is
//    tau(psi) = g [c sin(45deg - theta - psi) - rho sin(theta)], zero at psi* = 45deg - theta -
//    asin(rho sin(theta) / c) = 28.8deg, where the barrier is B = dU(psi*) = 0.3203 J/kg (sharp:
//    (a/sqrt2)(1 - cos(45deg - theta)) g = 0.3717).
//  - So E after impact k follows E_{k+1} = r^2 (E_k + G), with fixed point r^2 G / (1 - r^2) =
//    0.1304 J/kg below B: rolling ends. (At theta = 20 degrees this cube's fixed point, 0.172,
//    is within 20 % of its barrier, 0.213; a sharp cube rolls for ever above about 28 degrees.)
//  - Start: rolling about the front edge with the centre of mass at v0 = 1.2 m/s,
//    E0 = v0^2 (I_G + |r_old|^2) / (2 |r_old|^2) = 0.9633 J/kg, three times B: it rolls over
//    once; after that impact E1 <= r^2 (E0 + G) = 0.2233 J/kg, 70 % of B: it does not roll over
//    again (more loss, from the impulse spread over the landing face, only lowers E1). The
//    distance is one roll length, 0.409 m.
//  - Time of the roll: K >= E0 - B and I <= I_max = I_G + (c + rho)^2 = 0.1089 m^2 (the contact
//    point on the rounded edge is at most c + rho from the centre), so omega >= 3.436 rad/s over
//    pi/2: t1 <= 0.457 s.
//  - Then it rocks on its face, each rock landing on the face's other edge (E times r^2,
//    omega times r). With E <= E1 the tilt stays below psi_E, dU(psi_E) = E1, psi_E = 13.1deg,
//    where the restoring torque is at least tau(psi_E) = 0.702 (tipping uphill it is larger). A
//    rock of energy E then rises for at most sqrt(2 I_max E) / tau_min (the kinetic energy at
//    psi is at least tau_min (psi_max - psi)) and falls as long, so all the rocking ends within
//    t_rock <= 2 sqrt(2 I_max E1) / (tau_min (1 - r)) = 0.943 s.
//  - The rest criterion (0.1 m/s for 1 s) counts a rock stopped from the start of its slow
//    spell: that start is at most t1 + t_rock (+ one step) = 1.40 s after release, and the
//    state reads stopped 1 s later.
// The test computes these bounds from the shape's own leaves by the formulas above.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <numbers>

#include "sim/ground/ground_material.h"
#include "sim/ground/rock_monitor.h"
#include "sim/world.h"
#include "tests/support/smooth_ball.h"
#include "tests/support/test_world.h"

namespace vf {
namespace {

constexpr double kG = 9.81;
constexpr double kTheta = 15.0 * std::numbers::pi / 180.0;
constexpr double kV0 = 1.2;  // m/s, the centre of mass of both rocks at release
const Vec3 kDown(std::cos(kTheta), 0, -std::sin(kTheta));   // downslope, along the plane
const Vec3 kNormal(std::sin(kTheta), 0, std::cos(kTheta));  // the plane's normal
const Vec3 kAxis = kNormal.cross(kDown);                    // rolling downslope turns about it

// The plane z = -x tan(theta) through the origin, as a terrain of 1 m cells over x in [-4, 16].
std::shared_ptr<const Heightfield> incline() {
  auto h = std::make_shared<Heightfield>(test::flatHeightfield(21, 9, 1.0, 0.0, -4.0, -4.0));
  for (int j = 0; j < h->ny; ++j)
    for (int i = 0; i < h->nx; ++i)
      h->z[static_cast<std::size_t>(j) * h->nx + i] = -(h->x0 + i) * std::tan(kTheta);
  return h;
}

test::RockFallWorld inclineWorld(const GroundMaterial& m) {
  auto g = std::make_shared<GroundMap>();
  g->materials.push_back(m);
  WorldDef def;
  def.terrain = incline();
  return test::RockFallWorld(def, test::groundLaws(g));
}

// The rounded square the cube rolls on (header comment), from its sphere tree's leaves, and the
// bounds derived there, per unit mass.
struct CubeRoll {
  double h = 0, rho = 0, c = 0, iG = 0;
  double dU(double psi) const {
    const double q = std::numbers::pi / 4;
    return kG * (std::cos(kTheta) * c * (std::cos(q - psi) - std::cos(q)) +
                 std::sin(kTheta) * (c * std::sin(q - psi) - c * std::sin(q) - rho * psi));
  }
  double tau(double psi) const {
    return kG * (c * std::sin(std::numbers::pi / 4 - kTheta - psi) - rho * std::sin(kTheta));
  }
  double rOld2() const { return h * h + (h + rho) * (h + rho); }
  double ratio() const { return (iG - h * h + (h + rho) * (h + rho)) / (iG + rOld2()); }
  double iMax() const { return iG + (c + rho) * (c + rho); }
  double rollLength() const { return 2 * h + rho * std::numbers::pi / 2; }
  double psiStar() const {
    return std::numbers::pi / 4 - kTheta - std::asin(rho * std::sin(kTheta) / c);
  }
};

CubeRoll cubeRoll(const Shape& s) {
  CubeRoll k;
  const SphereTreeLevel& leaves = s.tree->leaves();
  for (const Vec3& p : leaves.centers) k.h = std::max(k.h, p.x());
  k.rho = leaves.radius;
  k.c = k.h * std::sqrt(2.0);
  k.iG = s.inertiaBody(1, 1) / s.mass;
  return k;
}

}  // namespace

TEST(Creep, OnItsRollingFrictionAngleAStoneRockRollsOnWhileASlipLawCubeStops) {
  auto cube = test::boxShape(0.4, 0.4, 0.4, 2600, 4);
  const CubeRoll k = cubeRoll(*cube);
  ASSERT_NEAR(k.h, 0.1875, 1e-6);  // the header's geometry (the voxel grid is padded by 1e-9)
  const double r = k.ratio(), B = k.dU(k.psiStar()), G = kG * std::sin(kTheta) * k.rollLength();
  const double e0 = 0.5 * kV0 * kV0 * (k.iG + k.rOld2()) / k.rOld2();
  const double e1 = r * r * (e0 + G);
  ASSERT_GT(e0, B);  // it rolls over once...
  ASSERT_LT(e1, B);  // ...and not twice
  const double t1 = std::numbers::pi / 2 / std::sqrt(2 * (e0 - B) / k.iMax());
  double lo = 0, hi = k.psiStar();  // psi_E: dU rises on [0, psi*]
  for (int i = 0; i < 60; ++i) (k.dU(0.5 * (lo + hi)) < e1 ? lo : hi) = 0.5 * (lo + hi);
  const double tRock = 2 * std::sqrt(2 * k.iMax() * e1) / (k.tau(hi) * (1 - r));
  const double tMove = t1 + tRock;

  // The slip law with eps_N = 0 and mu(s) = 2 at any slippage (mu_min = mu_max: the scene keys
  // allow it), far above tan(theta) = 0.27: the cube never slides.
  GroundMaterial slip;
  slip.name = "slip";
  slip.law = GroundLawKind::kSlip;
  slip.restitution = 0;
  slip.muMin = slip.muMax = 2;
  slip.kappa = 3;
  slip.beta = 185;
  test::RockFallWorld slipRock = inclineWorld(slip);
  World& slipWorld = slipRock.world;
  const double rest = slipRock.rockFall.def().rest.time, maxStep = slipWorld.def().maxStep;
  BodyDef c;
  c.shape = cube;
  c.orientation = Quat(Eigen::AngleAxisd(kTheta, Vec3::UnitY()));  // a face on the plane
  c.position = kNormal * test::restOffset(*cube);
  const double omega0 = kV0 / std::sqrt(k.rOld2());  // about the front edge's contact
  c.angularVelocity = omega0 * kAxis;
  c.velocity = omega0 * (k.h * kNormal + (k.h + k.rho) * kDown);
  slipWorld.addBody(c);
  const double T = tMove + maxStep + rest + maxStep;
  slipWorld.advanceTo(T);
  const RockOutcome& cubeEnd = slipRock.rockFall.outcomes()[0];
  EXPECT_EQ(cubeEnd.state, RockState::kStopped) << rockStateName(cubeEnd.state);
  EXPECT_LE(cubeEnd.endTime, tMove + maxStep) << "its slow spell began by then";
  // One roll: half a roll length either side tells one roll from none or two.
  const double travelled = (slipWorld.state(0).x - c.position).dot(kDown);
  EXPECT_GT(travelled, 0.5 * k.rollLength());
  EXPECT_LT(travelled, 1.5 * k.rollLength());

  // STONE's law with mu_r = tan(theta): about the contact, gravity's torque m g sin(theta) R and
  // the brake's mu_r R m g cos(theta) cancel, so a ball rolling at v0 keeps v0: at T it is still
  // moving, and no slower than v0 less one step of gravity's pull along the slope (by which the
  // brake and friction lag a step). This is the creep. (With any larger mu_r the ball slows as
  // 5/7 g (mu_r cos(theta) - sin(theta)); at mu_r = 1.5 tan(theta) it is at 0.1 m/s by T.)
  GroundMaterial stone;
  stone.name = "stone";
  stone.restitution = 0;
  stone.friction = 0.8;
  stone.rollingResistance = std::tan(kTheta);
  test::RockFallWorld stoneRock = inclineWorld(stone);
  World& stoneWorld = stoneRock.world;
  const double R = 0.25;
  BodyDef b;
  b.shape = test::smoothBall(R, 100);
  b.position = kNormal * R;
  b.velocity = kV0 * kDown;
  b.angularVelocity = kV0 / R * kAxis;
  stoneWorld.addBody(b);
  stoneWorld.advanceTo(T);
  EXPECT_EQ(stoneRock.rockFall.outcomes()[0].state, RockState::kMoving);
  EXPECT_GE(stoneWorld.velocity(0).dot(kDown),
            kV0 - kG * std::sin(kTheta) * stoneWorld.totals().dtMax);
}

}  // namespace vf

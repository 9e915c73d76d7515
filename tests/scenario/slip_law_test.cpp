// The slip law (RAMMS-type slippage-dependent friction, Leine et al. 2014; sim/solve/slip_law.cpp)
// against closed forms and an independent integration: a sliding block decelerates by mu(s) g
// with s its path in contact, a Newton impact with eps_N = 0 leaves no rebound, s decays in
// flight as exp(-beta t), and on mixed ground s grows on slip classes only while STONE's law
// acts on its own classes. Each tolerance is derived in the comment beside it.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <numbers>

#include "sim/ground/ground_material.h"
#include "sim/ground/rock_monitor.h"
#include "sim/world.h"
#include "tests/support/test_world.h"

namespace vf {
namespace {

constexpr double kG = 9.81;

std::shared_ptr<const GroundMap> oneMaterial(const GroundMaterial& m) {
  auto g = std::make_shared<GroundMap>();
  g->materials.push_back(m);
  return g;
}

// A slip material of the given coefficients (mu_min, mu_max, kappa 1/m, beta 1/s, eps_N).
GroundMaterial slipMaterial(double muMin, double muMax, double kappa, double beta, double eps) {
  GroundMaterial m;
  m.name = "slip";
  m.law = GroundLawKind::kSlip;
  m.muMin = muMin;
  m.muMax = muMax;
  m.kappa = kappa;
  m.beta = beta;
  m.restitution = eps;
  return m;
}

// A flat block: 0.4 x 0.4 m, 0.1 m high, so that friction up to mu = 4 cannot tip it (its
// half-width over its centre's height), and every mu(s) here slides it flat.
std::shared_ptr<const Shape> flatBlock() { return test::boxShape(0.4, 0.4, 0.1, 800, 4); }

// The reference, independent of the simulator: dv/dt = -g (mu(s) cos(theta) - sin(theta)),
// ds/dt = v, by classical Runge-Kutta with step h (error O(h^4)), until v reaches 0.
struct SlideReference {
  GroundCoefficients c;
  double theta = 0;
  double h = 1e-6;
  // v and s at time t (v stays 0 once it has reached it on a slope it can hold).
  void at(double v0, double t, double& v, double& s) const {
    auto accel = [&](double sv) {
      return -kG * (slipFriction(c, sv) * std::cos(theta) - std::sin(theta));
    };
    v = v0;
    s = 0;
    const int n = static_cast<int>(std::lround(t / h));
    for (int k = 0; k < n && v > 0; ++k) {
      const double k1v = accel(s), k1s = v;
      const double k2v = accel(s + h / 2 * k1s), k2s = v + h / 2 * k1v;
      const double k3v = accel(s + h / 2 * k2s), k3s = v + h / 2 * k2v;
      const double k4v = accel(s + h * k3s), k4s = v + h * k3v;
      v += h / 6 * (k1v + 2 * k2v + 2 * k3v + k4v);
      s += h / 6 * (k1s + 2 * k2s + 2 * k3s + k4s);
    }
    v = std::max(v, 0.0);
  }
};

}  // namespace

// A block sliding on a level plane of Leine et al. 2014's demonstration material (mu from 0.2 to
// 1.3, kappa 0.7 1/m) at v0 = 3 m/s: v(t) and s(t) follow dv/dt = -g mu(s), ds/dt = v until it
// stops (after 0.62 s and 1.05 m). Constant friction at mu_min or at mu(1.05 m) = 0.64 would
// miss v by 0.56 and 0.75 m/s at t = 0.3 s, over 25 times the tolerance there (0.021 m/s).
TEST(SlipLaw, ASlidingBlockDeceleratesByMuOfItsSlippageTimesG) {
  const double v0 = 3.0, dt = 1e-3;
  const GroundMaterial m = *groundPreset("leine2014_demo", 0.8);
  WorldDef def;
  def.groundHeight = 0.0;
  def.step = StepRule::fixed(dt);
  test::RockFallWorld rock(def, test::groundLaws(oneMaterial(m)));
  World& world = rock.world;
  auto s = flatBlock();
  BodyDef b;
  b.shape = s;
  b.position = Vec3(0, 0, test::restOffset(*s));  // the bottom leaves just touch the plane
  b.velocity = Vec3(v0, 0, 0);
  world.addBody(b);
  const SlideReference ref{m};
  // Tolerance, first order in dt (the method is first order):
  //  - friction may start a step late (the first step's spheres only just touch): g mu_max dt;
  //  - a step's friction reads s as it stood at the step's start, at most v0 dt behind s(t), so
  //    mu lags by at most mu'_max v0 dt, mu'_max = (2/pi)(mu_max - mu_min) kappa: over time t the
  //    velocity drifts by at most g mu'_max v0 dt t;
  //  - an error e_s in s feeds back as de_v/dt = -g mu' e_s, de_s/dt = e_v, which grows errors
  //    at most like cosh(w t), w = sqrt(g mu'_max).
  // s is the sum of |v| dt after each step's solve, a Riemann sum of the simulated v: it is off
  // by the integral of v's error plus one step's v0 dt.
  const double muSlope = 2 / std::numbers::pi * (m.muMax - m.muMin) * m.kappa;
  const double w = std::sqrt(kG * muSlope);
  double t = 0;
  bool moved = false;
  for (int k = 1; k <= 12; ++k) {
    world.advanceTo(0.05 * k);
    t = world.time();
    double v, sr;
    ref.at(v0, t, v, sr);
    const double tolV = kG * dt * (m.muMax + muSlope * v0 * t) * std::cosh(w * t);
    const double tolS = tolV * t + v0 * dt;
    EXPECT_NEAR(world.velocity(0).x(), v, tolV) << "t = " << t;
    EXPECT_NEAR(rock.rockFall.slippage(0), sr, tolS) << "t = " << t;
    moved = moved || v > 0;
  }
  ASSERT_TRUE(moved);
  // At rest after the reference's stop (0.62 s): s holds the path, and equals the distance slid
  // (a flat slide: the centre's path is its displacement), to the Euler error of both sums.
  world.advanceTo(1.0);
  double vEnd, sEnd;
  ref.at(v0, 1.0, vEnd, sEnd);
  EXPECT_EQ(vEnd, 0.0);
  EXPECT_LT(world.velocity(0).norm(), kG * dt);
  EXPECT_NEAR(rock.rockFall.slippage(0), world.state(0).x.x(), 2 * v0 * dt);
  EXPECT_NEAR(world.state(0).x.y(), 0, 1e-9);
}

// A Newton impact (eq. 38): the normal velocity after the landing step is -eps_N times the one
// before. The preset's eps_N = 0 leaves the block on the ground; a slip material with eps_N =
// 0.5 rebounds at half the speed, which shows the test would see a rebound. The tangential
// velocity loses what Coulomb friction at mu(s = 0) = mu_min takes, mu_min times the normal
// velocity change, and nothing more: no tangential restitution (eq. 40). The solver may pass
// over the contacts until a pass changes nothing (impulse.cpp), so every contact meets its
// target to rounding: 1e-12 m/s covers the sums over the face's few hundred contacts.
TEST(SlipLaw, ANewtonImpactWithEpsNZeroLeavesNoRebound) {
  const double h = 0.5, vx = 2.0, dt = 1e-3;
  struct Landing {
    double vzBefore = 0, vzAfter = 0, vxAfter = 0;
    std::uint64_t passes = 0;
  };
  auto land = [&](const GroundMaterial& m) {
    WorldDef def;
    def.groundHeight = 0.0;
    def.step = StepRule::fixed(dt);
    def.solverIterations = 1000;
    test::RockFallWorld rock(def, test::groundLaws(oneMaterial(m)));
    World& world = rock.world;
    auto s = flatBlock();
    BodyDef b;
    b.shape = s;
    b.position = Vec3(0, 0, test::restOffset(*s) + h);
    b.velocity = Vec3(vx, 0, 0);
    world.addBody(b);
    Landing l;
    while (world.time() < 1.0) {
      const double before = world.velocity(0).z();
      world.step(dt);
      if (world.velocity(0).z() > before + kG * dt) {  // an impulse pushed it up: the landing
        l.vzBefore = before - kG * dt;                 // with this step's gravity
        l.vzAfter = world.velocity(0).z();
        l.vxAfter = world.velocity(0).x();
        l.passes = world.lastStep().solverPasses;
        break;
      }
    }
    return l;
  };
  const GroundMaterial demo = *groundPreset("leine2014_demo", 0.8);
  const Landing still = land(demo);
  const Landing bouncy = land(slipMaterial(demo.muMin, demo.muMax, demo.kappa, demo.beta, 0.5));
  const double vImpact = std::sqrt(2 * kG * h);
  // The landing happens within a step of the closed-form time: the speed within g dt of it.
  EXPECT_NEAR(-still.vzBefore, vImpact, 2 * kG * dt);
  EXPECT_LT(still.passes, 1000u) << "the solve stopped by its pass count, not converged";
  EXPECT_LT(bouncy.passes, 1000u) << "the solve stopped by its pass count, not converged";
  // eps_N = 0: the contacts' target normal velocity is 0.
  EXPECT_NEAR(still.vzAfter, 0.0, 1e-12);
  EXPECT_NEAR(bouncy.vzAfter, -0.5 * bouncy.vzBefore, 1e-12);
  // No tangential restitution: only Coulomb friction at mu_min (s = 0 before the first contact).
  EXPECT_NEAR(still.vxAfter, vx - demo.muMin * (still.vzAfter - still.vzBefore), 1e-12);
  EXPECT_NEAR(bouncy.vxAfter, vx - demo.muMin * (bouncy.vzAfter - bouncy.vzBefore), 1e-12);
}

// Out of contact s decays as exp(-beta t) (eq. 47): a block thrown onto the plane at 3 m/s
// slides during its landing, rebounds (eps_N = 0.6) and flies to its apex. From the last step
// with ground contact (s0 at t0) to the apex, s = s0 exp(-beta (t - t0)): the step applies the
// exact factor exp(-beta dt), so only the rounding of the product of ~190 factors separates
// them (1e-12 relative). Without the decay, or with it in contact too, s would be off by
// exp(-beta (t - t0)) = 0.4 or more.
TEST(SlipLaw, SlippageDecaysOutOfContactAsExpOfMinusBetaT) {
  const double h = 0.5, dt = 1e-3, beta = 5.0;
  WorldDef def;
  def.groundHeight = 0.0;
  def.step = StepRule::fixed(dt);
  test::RockFallWorld rock(def,
                           test::groundLaws(oneMaterial(slipMaterial(0.2, 1.3, 0.7, beta, 0.6))));
  World& world = rock.world;
  auto s = flatBlock();
  BodyDef b;
  b.shape = s;
  b.position = Vec3(0, 0, test::restOffset(*s) + h);
  b.velocity = Vec3(3.0, 0, 0);
  world.addBody(b);
  double s0 = 0, t0 = -1;
  bool rising = false;
  while (world.time() < 1.0) {
    const double before = rock.rockFall.slippage(0);
    world.step(dt);
    if (rock.rockFall.slippage(0) > before) {  // grew: a step in contact
      s0 = rock.rockFall.slippage(0), t0 = world.time();
      continue;
    }
    if (t0 < 0) {
      EXPECT_EQ(rock.rockFall.slippage(0), 0.0) << "s before the first contact";
      continue;
    }
    rising = rising || world.velocity(0).z() > 0;
    if (rising && world.velocity(0).z() <= 0) break;  // the apex
  }
  ASSERT_GT(s0, 0.0) << "the landing slid";
  ASSERT_TRUE(rising) << "the block rebounded";
  const double flight = world.time() - t0;
  EXPECT_GT(flight, 0.15);  // about 0.6 * 3.1 m/s / g = 0.19 s to the apex
  EXPECT_NEAR(rock.rockFall.slippage(0) / (s0 * std::exp(-beta * flight)), 1.0, 1e-12);
  EXPECT_LT(rock.rockFall.slippage(0), 0.5 * s0);
}

// Mixed ground: a class raster with the slip preset on x < -0.5 m and a STONE material (Coulomb
// mu 0.3) beyond. A block sliding at 7 m/s from x = -3 m over both: on the slip class s grows by
// the path; on the STONE class s decays (exactly, step by step, at the slip class's beta) and the
// block decelerates by the STONE material's mu g; the first touch on slip ground is no STONE
// landing, so no bounce is counted; and the block comes to rest as the rock monitor says.
TEST(SlipLaw, OnMixedGroundSlippageGrowsOnSlipClassesAndStoneActsOnItsOwn) {
  const double v0 = 7.0, dt = 1e-3, muStone = 0.3;
  auto terrain =
      std::make_shared<const Heightfield>(test::flatHeightfield(41, 11, 1.0, 0.0, -5.0, -5.0));
  auto classes = std::make_shared<Heightfield>(*terrain);
  for (int j = 0; j < classes->ny; ++j)
    for (int i = 0; i < classes->nx; ++i)
      classes->z[static_cast<std::size_t>(j) * classes->nx + i] = classes->x0 + i < 0 ? 1 : 2;
  auto g = std::make_shared<GroundMap>();
  const GroundMaterial slip = *groundPreset("leine2014_demo", 0.8);
  GroundMaterial stone = *groundPreset("glacial_deposits", muStone);
  g->materials = {stone, slip, stone};
  g->materialOfClass = {-1, 1, 2};
  g->classes = classes;
  WorldDef def;
  def.terrain = terrain;
  def.step = StepRule::fixed(dt);
  test::RockFallWorld rock(def, test::groundLaws(g));
  World& world = rock.world;
  auto s = flatBlock();
  BodyDef b;
  b.shape = s;
  b.position = Vec3(-3, 0, test::restOffset(*s));
  b.velocity = Vec3(v0, 0, 0);
  world.addBody(b);
  // The block's leaves reach 0.2 m (and a leaf radius, 0.02 m) from its centre; the classes of
  // the samples at x = -1 and 0 meet at x = -0.5: the block is wholly on one class when its
  // centre is more than 0.25 m from there.
  bool sawSlip = false, sawStone = false;
  while (world.time() < 3.0 && world.velocity(0).norm() > 0.5) {
    const double x = world.state(0).x.x(), sBefore = rock.rockFall.slippage(0);
    const Vec3 vBefore = world.velocity(0);
    world.step(dt);
    const double x1 = world.state(0).x.x();
    if (x > -2.9 && x1 < -0.8) {  // on slip ground, in contact: s grows by |v| dt
      sawSlip = true;
      EXPECT_NEAR(rock.rockFall.slippage(0) - sBefore,
                  world.velocity(0).norm() * world.lastStep().dt, 1e-12);
    } else if (x > -0.2) {  // on STONE ground: s decays at the slip class's beta, v by mu g dt
      sawStone = true;
      EXPECT_EQ(rock.rockFall.slippage(0), sBefore * std::exp(-slip.beta * world.lastStep().dt));
      // Coulomb at the STONE material's mu: the friction impulse per unit mass is at most mu
      // times the normal one, N = g dt + dv_z on level ground, and along the slide at least
      // mu N cos(phi), phi the largest angle between a contact point's slip and the centre's
      // velocity: tan(phi) = |w_z| R / |v_h| with R the block's bounding radius (crossing the
      // class border has given it a small yaw). Rounding of the velocities: 1e-12 m/s.
      const Vec3 dv = world.velocity(0) - vBefore;
      const double normal = kG * dt + dv.z();
      const Vec3 along(vBefore.x(), vBefore.y(), 0);
      const double slowed = -dv.dot(along.normalized());
      const double phi = std::atan(std::abs(world.angularVelocity(0).z()) *
                                   s->tree->boundingRadius / along.norm());
      EXPECT_LE(slowed, muStone * normal + 1e-12) << "x = " << x;
      EXPECT_GE(slowed, muStone * normal * std::cos(phi) - 1e-12) << "x = " << x;
    }
  }
  EXPECT_TRUE(sawSlip);
  EXPECT_TRUE(sawStone);
  world.advanceTo(world.time() + 3.0);
  ASSERT_EQ(rock.rockFall.outcomes().size(), 1u);
  EXPECT_EQ(rock.rockFall.outcomes()[0].bounces, 0)
      << "a touch on slip ground counted as STONE bounce";
  EXPECT_EQ(rock.rockFall.outcomes()[0].state, RockState::kStopped);
}

}  // namespace vf

namespace vf {

// Determinism: blocks sliding and colliding on slip ground with per-cell variability give the
// same trajectory, bit for bit, on 1, 2 and 3 threads (the narrow phase's blocks and the
// solver's islands are merged in a fixed order; the slippage is updated body by body).
TEST(SlipLaw, TheSameBitsOnAnyThreadCount) {
  auto terrain =
      std::make_shared<const Heightfield>(test::flatHeightfield(21, 21, 1.0, 0.0, -10.0, -10.0));
  auto g = std::make_shared<GroundMap>();
  g->materials.push_back(*groundPreset("ramms_chant_sura", 0.8));
  g->variability = 0.1;
  g->variabilitySeed = 9;
  g->cells = terrain;
  auto run = [&](int threads, double& s0) {
    WorldDef def;
    def.terrain = terrain;
    def.threads = threads;
    test::RockFallWorld rock(def, test::groundLaws(g));
    World& world = rock.world;
    auto s = test::boxShape(0.4, 0.4, 0.1, 800, 3);
    for (int i = 0; i < 6; ++i) {
      BodyDef b;
      b.shape = s;
      b.position = Vec3(-3.0 + 0.9 * i, 0.3 * (i % 3), 0.3 + 0.15 * i);
      b.velocity = Vec3(2.0 - 0.7 * i, 0.5 * (i % 2), 0);
      b.angularVelocity = Vec3(0.5 * i, 1.0, 0);
      world.addBody(b);
    }
    world.advanceTo(1.0);
    s0 = rock.rockFall.slippage(0);
    return world.stepsHash();
  };
  double s1 = 0, s2 = 0, s3 = 0;
  const std::uint64_t h1 = run(1, s1);
  EXPECT_EQ(run(2, s2), h1);
  EXPECT_EQ(run(3, s3), h1);
  EXPECT_GT(s1, 0.0) << "the blocks never slid on the ground";
  EXPECT_EQ(s2, s1);
  EXPECT_EQ(s3, s1);
}

}  // namespace vf

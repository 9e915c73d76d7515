// Rock fall on terrain: ground materials, rolling resistance, terrain edges and holes.
// Each tolerance is derived from the method (step dt, voxel level) in the comment beside it.
#include <gtest/gtest.h>

#include <cmath>

#include "sim/ground/ground_material.h"
#include "sim/world.h"
#include "tests/sim/test_meshes.h"
#include "tests/support/test_world.h"

namespace vf {
namespace {

constexpr double kG = 9.81;

std::shared_ptr<const GroundMap> oneMaterial(double restitution, double friction, double rolling) {
  auto g = std::make_shared<GroundMap>();
  GroundMaterial m;
  m.name = "test";
  m.restitution = restitution;
  m.friction = friction;
  m.rollingResistance = rolling;
  g->materials.push_back(m);
  return g;
}

}  // namespace

// A ball whose sphere tree is one sphere of radius r at its centre, with the inertia of a
// solid sphere: it rolls on a plane without the bumps of a voxelised surface (a level-5
// icosphere hops from leaf to leaf and loses half its speed in 1 s with no rolling resistance
// at all), so the rolling law can be checked against its closed form alone.
std::shared_ptr<const Shape> smoothBall(double r, double mass) {
  auto s = std::make_shared<Shape>();
  s->name = "smooth ball";
  s->mesh = test::icosphere(2, r);
  s->mass = mass;
  s->volume = 4.0 / 3.0 * M_PI * r * r * r;
  s->inertiaBody = 0.4 * mass * r * r * Mat3::Identity();
  s->inertiaBodyInv = s->inertiaBody.inverse();
  s->diameter = 2 * r;
  s->meshOrigin = Vec3::Zero();
  auto tree = std::make_shared<SphereTree>();
  SphereTreeLevel leaf;
  leaf.edge = 2 * r / std::sqrt(3.0);
  leaf.radius = r;
  leaf.centers = {Vec3::Zero()};
  leaf.childBegin = {0, 0};
  tree->levels = {leaf};
  tree->boundingRadius = r;
  s->tree = tree;
  return s;
}

// A sphere rolling without slip on level ground with rolling resistance mu_r stops after
// d = 7 v0^2 / (10 mu_r g) (Azzoni et al. 1995: v0^2 / (2 A mu_r g), A = 5/7 for a solid
// sphere).
TEST(Rockfall, RollingSphereStopsAtTheRollingResistanceDistance) {
  const double r = 0.25, v0 = 2.0, muR = 0.3;
  const double d = 7 * v0 * v0 / (10 * muR * kG);
  auto ball = smoothBall(r, 100);
  WorldDef def;
  def.groundHeight = 0.0;
  def.ground = oneMaterial(0.0, 0.8, muR);
  World world(def);
  BodyDef b;
  b.shape = ball;
  b.position = Vec3(0, 0, r);
  b.velocity = Vec3(v0, 0, 0);
  b.angularVelocity = Vec3(0, v0 / r, 0);  // rolling without slip towards +x
  world.addBody(b);
  const double tStop = v0 / (5.0 / 7.0 * muR * kG);
  world.advanceTo(tStop + 1.0);
  const double dt = world.totals().dtMax;
  // Tolerance: per step the brake takes mu_r r N dt of angular momentum about the contact and
  // friction converts it into speed one step later, so the speed lags the closed form by one
  // step of deceleration (a dt) and the position integrates it with Euler's v0 dt / 2, as in
  // the Coulomb sliding test; 2 v0 dt covers both.
  EXPECT_NEAR(world.state(0).x.x(), d, 2 * v0 * dt);
  EXPECT_LT(world.velocity(0).norm(), kG * dt) << "at rest: below what gravity adds in a step";
  EXPECT_NEAR(world.state(0).x.y(), 0, 1e-9);
  // Without rolling resistance (the paper's model) the same ball rolls on (it keeps over 99 %
  // of v0 over the same time): the stop above is the rolling law's doing.
  WorldDef paper;
  paper.groundHeight = 0.0;
  paper.contact.restitutionBodyGround = 0.0;
  World free(paper);
  free.addBody(b);
  free.advanceTo(tStop + 1.0);
  EXPECT_GT(free.velocity(0).x(), 0.99 * v0);
  EXPECT_GT(free.state(0).x.x(), 3 * d);
}

}  // namespace vf

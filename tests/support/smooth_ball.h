// A ball whose collision is exactly a sphere, for tests of rolling laws.
#pragma once

#include <cmath>
#include <memory>

#include "sim/shape/shape.h"
#include "tests/sim/test_meshes.h"

namespace vf::test {

// A ball whose sphere tree is one sphere of radius r at its centre, with the inertia of a
// solid sphere: it rolls on a plane without the bumps of a voxelised surface (a level-5
// icosphere hops from leaf to leaf and loses half its speed in 1 s with no rolling resistance
// at all), so the rolling law can be checked against its closed form alone.
inline std::shared_ptr<const Shape> smoothBall(double r, double mass) {
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
  finishSphereTree(*tree);  // bounding radius r
  s->tree = tree;
  return s;
}

}  // namespace vf::test

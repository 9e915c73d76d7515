// Release placement (sim/solve/release.h) against what it promises, with the answers worked out
// from the geometry by hand (box meshes, a planar slope), not from the code:
//   - over the floor alone, the lowest mesh point ends `clearance` above it;
//   - over a planar slope, the vertex nearest the surface (measured straight down) ends
//     `clearance` above it;
//   - a body of the pile under the footprint (one in the last step's contacts, a sleeper, any
//     body before the first step) lifts it to `clearance` above that body's mesh top;
//   - an airborne body (touching nothing) under the footprint does not, unless the new body
//     would be born inside its box grown by both leaf radii: then it goes above that box;
//   - with nothing below (no floor, no terrain, no body) it stays where it is;
//   - overlapsActiveBody sees leaf spheres that touch, and only those of active bodies.
// Tolerances: the lift is one subtraction and one addition of numbers of order 1 m, so the
// placed heights agree with the hand-computed ones to a few ulps (1e-12 m).
#include "sim/solve/release.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "tests/support/test_world.h"

namespace vf {
namespace {

constexpr double kTol = 1e-12;

struct Bodies {
  std::vector<BodyInfo> info;
  std::vector<BodyState> states;
  int add(std::shared_ptr<const Shape> s, const Vec3& x, bool active = true) {
    BodyInfo b;
    b.shape = std::move(s);
    b.invMass = 1.0 / b.shape->mass;
    b.active = active;
    BodyState y;
    y.x = x;
    info.push_back(b);
    states.push_back(y);
    return static_cast<int>(info.size()) - 1;
  }
};

double lowestZ(const Bodies& w, int id, double lift) {
  double z = INFINITY;
  for (const Vec3& v : w.info[id].shape->mesh.vertices)
    z = std::min(z, w.states[id].x.z() + lift + v.z());  // unrotated
  return z;
}

TEST(Release, OverTheFloorTheLowestPointEndsClearanceAboveIt) {
  Bodies w;
  const int id = w.add(test::boxShape(0.4, 0.3, 0.2, 800, 3), Vec3(1, 2, 5));
  const double lift = releaseLift(id, 0.25, w.info, w.states, {}, true, {0.5, nullptr});
  EXPECT_NEAR(lowestZ(w, id, lift), 0.5 + 0.25, kTol);  // box bottom at z - 0.1
  EXPECT_NEAR(lift, 0.75 - (5 - 0.1), kTol);            // negative: lowered onto the floor
}

TEST(Release, OverASlopeTheVertexNearestTheSurfaceEndsClearanceAboveIt) {
  // z = 0.5 x + 1 on a grid from x = 0 to 10: for an axis-aligned box the bottom vertices on
  // the uphill side (largest x) are nearest the surface.
  Heightfield slope = test::flatHeightfield(11, 11, 1.0, 0.0);
  for (int j = 0; j < slope.ny; ++j)
    for (int i = 0; i < slope.nx; ++i) slope.z[j * slope.nx + i] = 0.5 * i + 1;
  slope.zMin = 1;
  slope.zMax = 6;
  Bodies w;
  const int id = w.add(test::boxShape(0.4, 0.3, 0.2, 800, 3), Vec3(4.3, 5.1, 20));
  const double lift = releaseLift(id, 0.1, w.info, w.states, {}, true, {std::nullopt, &slope});
  const double uphillBottom = w.states[id].x.z() - 0.1 + lift;  // at x = 4.3 + 0.2
  EXPECT_NEAR(uphillBottom - (0.5 * 4.5 + 1), 0.1, kTol);
  // The floor far below changes nothing; a floor above the slope there wins.
  EXPECT_NEAR(releaseLift(id, 0.1, w.info, w.states, {}, true, {-3.0, &slope}), lift, kTol);
  const double onHighFloor = releaseLift(id, 0.1, w.info, w.states, {}, true, {7.0, &slope});
  EXPECT_NEAR(lowestZ(w, id, onHighFloor), 7.1, kTol);
}

TEST(Release, APileBodyUnderTheFootprintLiftsItAboveThatBody) {
  auto box = test::boxShape(0.3, 0.3, 0.3, 800, 3);
  Bodies w;
  const int below = w.add(box, Vec3(0, 0, 0.15));       // resting on the floor, top at 0.30
  const int placed = w.add(box, Vec3(0.1, 0.05, 2.0));  // footprints overlap
  Contact onFloor;
  onFloor.a = below;
  const std::vector<Contact> last{onFloor};
  // In the last step's contacts, asleep, or before the first step: the pile.
  double lift = releaseLift(placed, 0.2, w.info, w.states, last, false, {0.0, nullptr});
  EXPECT_NEAR(lowestZ(w, placed, lift), 0.30 + 0.2, kTol);
  lift = releaseLift(placed, 0.2, w.info, w.states, {}, true, {0.0, nullptr});
  EXPECT_NEAR(lowestZ(w, placed, lift), 0.30 + 0.2, kTol);
  w.info[below].sleeping = true;
  lift = releaseLift(placed, 0.2, w.info, w.states, {}, false, {0.0, nullptr});
  EXPECT_NEAR(lowestZ(w, placed, lift), 0.30 + 0.2, kTol);
  // Beside the footprint it is not under the body: the floor decides.
  w.states[placed].x.x() = 1.0;
  lift = releaseLift(placed, 0.2, w.info, w.states, last, false, {0.0, nullptr});
  EXPECT_NEAR(lowestZ(w, placed, lift), 0.2, kTol);
}

TEST(Release, AnAirborneBodyLiftsItOnlyIfItWouldBeBornInsideIt) {
  auto box = test::boxShape(0.3, 0.3, 0.3, 800, 3);
  const double pad = 2 * box->tree->leaves().radius;  // both bodies' leaf radii
  Bodies w;
  const int falling = w.add(box, Vec3(0, 0, 3.0));  // touches nothing: mesh from 2.85 to 3.15
  const int placed = w.add(box, Vec3(0.1, 0, 5.0));
  // Placed on the floor with 0.2 m clearance it spans 0.2 to 0.5: clear of the falling box.
  double lift = releaseLift(placed, 0.2, w.info, w.states, {}, false, {0.0, nullptr});
  EXPECT_NEAR(lowestZ(w, placed, lift), 0.2, kTol);
  // Lower the falling box into that place: the new body goes above its grown box, and the
  // clearance is kept from there.
  w.states[falling].x.z() = 0.4;
  lift = releaseLift(placed, 0.2, w.info, w.states, {}, false, {0.0, nullptr});
  EXPECT_NEAR(lowestZ(w, placed, lift), 0.4 + 0.15 + pad + 0.2, kTol);
  // An inactive body (not yet released) is not there at all.
  w.info[falling].active = false;
  lift = releaseLift(placed, 0.2, w.info, w.states, {}, false, {0.0, nullptr});
  EXPECT_NEAR(lowestZ(w, placed, lift), 0.2, kTol);
}

TEST(Release, WithNothingBelowTheBodyStaysWhereItIs) {
  Bodies w;
  const int id = w.add(test::boxShape(0.3, 0.3, 0.3, 800, 3), Vec3(0, 0, 1));
  EXPECT_EQ(releaseLift(id, 0.2, w.info, w.states, {}, true, {std::nullopt, nullptr}), 0.0);
  // A slope that does not reach under it is not below it either.
  const Heightfield away = test::flatHeightfield(3, 3, 1.0, 0.0, 10, 10);
  EXPECT_EQ(releaseLift(id, 0.2, w.info, w.states, {}, true, {std::nullopt, &away}), 0.0);
}

TEST(Release, OverlapsActiveBodySeesTouchingLeafSpheresOfActiveBodiesOnly) {
  auto box = test::boxShape(0.3, 0.3, 0.3, 800, 3);
  Bodies w;
  const int a = w.add(box, Vec3(0, 0, 1));
  const int b = w.add(box, Vec3(0.25, 0, 1));  // meshes overlap by 5 cm
  EXPECT_TRUE(overlapsActiveBody(b, w.info, w.states));
  w.info[a].active = false;
  EXPECT_FALSE(overlapsActiveBody(b, w.info, w.states));
  w.info[a].active = true;
  w.states[b].x.x() = 0.6;  // 30 cm apart, far more than two leaf radii
  EXPECT_FALSE(overlapsActiveBody(b, w.info, w.states));
}

}  // namespace
}  // namespace vf

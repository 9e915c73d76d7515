// Sweep and prune (sim/collide/broad_phase.cpp, in strips along y) against an all-pairs
// bounding-sphere test, on random clouds of bodies with inactive and static ones
// mixed in: the same pairs in the same (a, b) order, whatever order the sweep starts from.
#include "sim/collide/broad_phase.h"

#include <gtest/gtest.h>

#include "sim/core/prng.h"
#include "tests/support/test_world.h"

namespace vf {
namespace {

std::vector<BodyPair> allPairs(const std::vector<BodyInfo>& bodies,
                               const std::vector<BodyState>& states) {
  std::vector<BodyPair> out;
  for (int a = 0; a < static_cast<int>(bodies.size()); ++a)
    for (int b = a + 1; b < static_cast<int>(bodies.size()); ++b) {
      if (!bodies[a].active || !bodies[b].active || (bodies[a].isStatic && bodies[b].isStatic))
        continue;
      const double ra = bodies[a].shape->tree->boundingRadius;
      const double rb = bodies[b].shape->tree->boundingRadius;
      const double reach =
          ra + rb + roundingSlack(states[a].x, ra) + roundingSlack(states[b].x, rb);
      if ((states[a].x - states[b].x).squaredNorm() < reach * reach) out.push_back({a, b});
    }
  return out;
}

void expectSame(const std::vector<BodyPair>& got, const std::vector<BodyPair>& want,
                const char* what) {
  ASSERT_EQ(got.size(), want.size()) << what;
  for (std::size_t k = 0; k < got.size(); ++k) {
    EXPECT_EQ(got[k].a, want[k].a) << what << ", pair " << k;
    EXPECT_EQ(got[k].b, want[k].b) << what << ", pair " << k;
  }
}

TEST(BroadPhase, SweepAndPruneFindsExactlyTheAllPairsResult) {
  const auto small = test::boxShape(0.3, 0.3, 0.3, 800, 2);
  const auto large = test::boxShape(1.5, 0.4, 0.4, 800, 2);
  Prng rng(9);
  std::size_t found = 0;
  std::vector<int> order;  // the sweep order kept from call to call, as World keeps it
  for (int round = 0; round < 20; ++round) {
    std::vector<BodyInfo> bodies(200);
    std::vector<BodyState> states(200);
    for (int i = 0; i < 200; ++i) {
      bodies[i].shape = rng.uniform() < 0.8 ? small : large;
      bodies[i].active = rng.uniform() < 0.9;
      bodies[i].isStatic = rng.uniform() < 0.2;
      // Some on a shared x so that interval ends tie; some on y values a strip width apart
      // (twice the large box's reach, so on the strips' edges) or sharing one.
      const double x = rng.uniform() < 0.1 ? 1.0 : rng.uniform(0, 8);
      const double strip = 2 * large->tree->boundingRadius;
      const double u = rng.uniform();
      const double y = u < 0.1   ? strip * static_cast<int>(rng.uniform(0, 5))
                       : u < 0.2 ? strip * static_cast<int>(rng.uniform(0, 5)) - 1e-12
                                 : rng.uniform(0, 8);
      states[i].x = Vec3(x, y, rng.uniform(0, 2));
    }
    std::vector<BodyPair> sap;
    findPairs(bodies, states, sap);
    const std::vector<BodyPair> brute = allPairs(bodies, states);
    ASSERT_EQ(sap.size(), brute.size()) << "round " << round;
    for (std::size_t k = 0; k < sap.size(); ++k) {
      EXPECT_EQ(sap[k].a, brute[k].a);
      EXPECT_EQ(sap[k].b, brute[k].b);
    }
    found += sap.size();
    // With the order kept from the last round (other positions: a shuffled start, which may
    // give up on insertion sort), from this state, and after every body moved a little (nearly
    // sorted: insertion sort), appended after a pair already in the list.
    std::vector<BodyPair> hinted;
    findPairs(bodies, states, hinted, &order);
    expectSame(hinted, brute, "from the last round's order");
    hinted.clear();
    findPairs(bodies, states, hinted, &order);
    expectSame(hinted, brute, "from this state's order");
    for (BodyState& y : states) y.x += Vec3(rng.uniform(-0.05, 0.05), rng.uniform(-0.05, 0.05), 0);
    const std::vector<BodyPair> moved = allPairs(bodies, states);
    hinted.assign(1, BodyPair{-7, -7});
    findPairs(bodies, states, hinted, &order);
    ASSERT_FALSE(hinted.empty());
    EXPECT_EQ(hinted[0].a, -7) << "what was in the list stays first";
    hinted.erase(hinted.begin());
    expectSame(hinted, moved, "after a small move");
  }
  EXPECT_GT(found, 1000u) << "the clouds are dense enough to test something";
}

}  // namespace
}  // namespace vf

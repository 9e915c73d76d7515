// The hierarchical descent of fig. 3 against a brute-force oracle that lives only here: every
// leaf sphere of A against every leaf sphere of B. Invariants checked on random poses:
//   - the descent finds exactly the brute-force leaf pairs (same set, no duplicates);
//   - swapping A and B gives the same pairs with flipped normals;
//   - normals are unit, depths positive and equal to r1 + r2 - |x1 - x2|;
//   - plane contacts are exactly the leaf spheres that cross the plane.
#include "sim/collide/narrow_phase.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <set>
#include <utility>

#include "sim/core/prng.h"
#include "tests/support/test_world.h"

namespace vf {
namespace {

Quat randomRotation(Prng& rng) {
  Quat q(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1));
  return q.normalized();
}

std::set<std::pair<std::uint32_t, std::uint32_t>> bruteForce(const Collider& a, const Collider& b) {
  std::set<std::pair<std::uint32_t, std::uint32_t>> out;
  const SphereTreeLevel& la = a.tree->leaves();
  const SphereTreeLevel& lb = b.tree->leaves();
  const double r = la.radius + lb.radius;
  for (std::uint32_t i = 0; i < la.centers.size(); ++i) {
    const Vec3 ca = a.x + a.R * la.centers[i];
    for (std::uint32_t j = 0; j < lb.centers.size(); ++j) {
      const Vec3 cb = b.x + b.R * lb.centers[j];
      if ((ca - cb).squaredNorm() < r * r) out.insert({i, j});
    }
  }
  return out;
}

class NarrowPhaseTest : public ::testing::TestWithParam<int> {};

TEST_P(NarrowPhaseTest, DescentFindsExactlyTheBruteForceLeafPairs) {
  const int level = GetParam();
  // A box and an L-ish non-cubic box of different sizes, so the trees differ.
  auto sa = test::boxShape(0.3, 0.3, 0.3, 800, level);
  auto sb = test::boxShape(0.5, 0.2, 0.25, 800, level);
  Prng rng(42 + level);
  int posesWithContacts = 0;
  for (int trial = 0; trial < 60; ++trial) {
    // Centres close enough that the bodies usually overlap somewhat.
    const Vec3 xa(0, 0, 0);
    const Vec3 xb(rng.uniform(-0.45, 0.45), rng.uniform(-0.45, 0.45), rng.uniform(-0.45, 0.45));
    const Collider a = sphereTreeCollider(0, *sa->tree, xa, randomRotation(rng));
    const Collider b = sphereTreeCollider(1, *sb->tree, xb, randomRotation(rng));
    std::vector<Contact> contacts;
    const std::uint64_t tests = collide(a, b, contacts);
    const auto expected = bruteForce(a, b);
    std::set<std::pair<std::uint32_t, std::uint32_t>> found;
    const double radii = sa->tree->leaves().radius + sb->tree->leaves().radius;
    for (const Contact& c : contacts) {
      EXPECT_TRUE(found.insert({c.leafA, c.leafB}).second) << "duplicate contact";
      EXPECT_NEAR(c.normal.norm(), 1.0, 1e-12);
      EXPECT_GT(c.depth, 0.0);
      EXPECT_EQ(c.a, 0);
      EXPECT_EQ(c.b, 1);
      // Recomputed here from the two leaf centres: depth = r_a + r_b - |x_a - x_b|, normal along
      // x_a - x_b, point midway (fig. 5). Rounding of metre-sized values: 1e-12.
      const Vec3 ca = a.x + a.R * sa->tree->leaves().centers[c.leafA];
      const Vec3 cb = b.x + b.R * sb->tree->leaves().centers[c.leafB];
      EXPECT_NEAR(c.depth, radii - (ca - cb).norm(), 1e-12);
      EXPECT_LT((c.normal - (ca - cb).normalized()).norm(), 1e-12);
      EXPECT_LT((c.point - 0.5 * (ca + cb)).norm(), 1e-12);
    }
    EXPECT_EQ(found, expected) << "trial " << trial;
    if (!expected.empty()) ++posesWithContacts;
    // The point of the hierarchy: fewer tests than all leaf pairs when contacts are few
    // (at levels 1-2 the leaves are too few for refinement to pay).
    if (level >= 3 && expected.size() < 10) {
      EXPECT_LT(tests, sa->tree->leaves().centers.size() * sb->tree->leaves().centers.size());
    }

    // Swapping A and B: same pairs, opposite normals, same points.
    std::vector<Contact> swapped;
    collide(b, a, swapped);
    ASSERT_EQ(swapped.size(), contacts.size());
    std::map<std::pair<std::uint32_t, std::uint32_t>, const Contact*> original;
    for (const Contact& c : contacts) original[{c.leafA, c.leafB}] = &c;
    std::set<std::pair<std::uint32_t, std::uint32_t>> back;
    for (const Contact& c : swapped) {
      back.insert({c.leafB, c.leafA});
      EXPECT_EQ(c.a, 1);
      EXPECT_EQ(c.b, 0);
      const auto it = original.find({c.leafB, c.leafA});
      if (it == original.end()) continue;  // reported by the set comparison below
      EXPECT_LT((c.normal + it->second->normal).norm(), 1e-12) << "normal not flipped";
      EXPECT_NEAR(c.depth, it->second->depth, 1e-12);
      EXPECT_LT((c.point - it->second->point).norm(), 1e-12);
    }
    EXPECT_EQ(back, expected);
  }
  EXPECT_GT(posesWithContacts, 10) << "the random poses should exercise contacts";
}

INSTANTIATE_TEST_SUITE_P(Levels, NarrowPhaseTest, ::testing::Values(1, 2, 3, 4));

TEST(NarrowPhase, SeparatedBodiesCostOneTest) {
  auto s = test::boxShape(0.3, 0.3, 0.3, 800, 4);
  const Collider a = sphereTreeCollider(0, *s->tree, Vec3(0, 0, 0), Quat::Identity());
  const Collider b = sphereTreeCollider(1, *s->tree, Vec3(5, 0, 0), Quat::Identity());
  std::vector<Contact> contacts;
  EXPECT_EQ(collide(a, b, contacts), 1u);  // the bounding-sphere test only (fig. 3 step 1)
  EXPECT_TRUE(contacts.empty());
}

TEST(NarrowPhase, DifferentLeafLevelsStillMatchBruteForce) {
  auto coarse = test::boxShape(0.3, 0.3, 0.3, 800, 2);
  auto fine = test::boxShape(0.4, 0.3, 0.2, 800, 4);
  Prng rng(7);
  for (int trial = 0; trial < 30; ++trial) {
    const Collider a = sphereTreeCollider(0, *coarse->tree, Vec3::Zero(), randomRotation(rng));
    const Collider b = sphereTreeCollider(1, *fine->tree,
                                          Vec3(rng.uniform(-0.4, 0.4), rng.uniform(-0.4, 0.4), 0.1),
                                          randomRotation(rng));
    std::vector<Contact> contacts;
    collide(a, b, contacts);
    std::set<std::pair<std::uint32_t, std::uint32_t>> found;
    for (const Contact& c : contacts) found.insert({c.leafA, c.leafB});
    EXPECT_EQ(found, bruteForce(a, b));
  }
}

TEST(NarrowPhase, PlaneContactsAreTheLeafSpheresCrossingThePlane) {
  auto s = test::boxShape(0.3, 0.2, 0.1, 800, 4);
  Prng rng(3);
  for (int trial = 0; trial < 40; ++trial) {
    const Collider a = sphereTreeCollider(0, *s->tree, Vec3(0.1, -0.2, rng.uniform(-0.1, 0.3)),
                                          randomRotation(rng));
    const double h = 0.02;
    const Collider plane = planeCollider(h);
    std::vector<Contact> contacts;
    collide(a, plane, contacts);
    const SphereTreeLevel& leaves = s->tree->leaves();
    std::set<std::uint32_t> expected, found;
    for (std::uint32_t i = 0; i < leaves.centers.size(); ++i)
      if ((a.x + a.R * leaves.centers[i]).z() - h < leaves.radius) expected.insert(i);
    for (const Contact& c : contacts) {
      found.insert(c.leafA);
      EXPECT_EQ(c.b, kGround);
      EXPECT_EQ(c.normal, Vec3::UnitZ());
      EXPECT_NEAR(c.point.z(), h, 1e-15);  // on the plane, to rounding of metre-sized values
      // depth = r - (z - h) of the leaf sphere, to rounding of metre-sized values.
      const double z = (a.x + a.R * leaves.centers[c.leafA]).z();
      EXPECT_NEAR(c.depth, leaves.radius - (z - h), 1e-12);
      EXPECT_GT(c.depth, 0.0);
    }
    EXPECT_EQ(found, expected) << "trial " << trial;
  }
}

}  // namespace
}  // namespace vf

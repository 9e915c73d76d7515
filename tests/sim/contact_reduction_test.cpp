// Contact reduction (sim/collide/contact_reduction.h):
//   - patches of at most kContactsPerPatch contacts, a single contact in particular, pass
//     through bit for bit (eq. 15 unchanged);
//   - a box face on the floor (a grid of leaf contacts) keeps its deepest contact and contacts
//     spanning the whole patch (the same x and y extent as all leaf contacts);
//   - two patches at 90 degrees (interlocked non-convex bodies) stay apart, each with its own
//     normal.
// The physics with reduction on (a flat landing rebounds to eps^2 h without tilting, a stack
// rests without creep) is checked by tests/scenario/analytic_test.cpp with the same bounds as
// without reduction.
#include "sim/collide/contact_reduction.h"

#include <gtest/gtest.h>

#include <algorithm>

#include "sim/collide/narrow_phase.h"
#include "tests/support/test_world.h"

namespace vf {
namespace {

Contact contactAt(int a, int b, const Vec3& p, const Vec3& n, double depth, std::uint32_t leaf) {
  Contact c;
  c.a = a;
  c.b = b;
  c.point = p;
  c.normal = n.normalized();
  c.depth = depth;
  c.leafA = leaf;
  return c;
}

bool same(const Contact& x, const Contact& y) {
  return x.a == y.a && x.b == y.b && x.point == y.point && x.normal == y.normal &&
         x.depth == y.depth && x.leafA == y.leafA && x.leafB == y.leafB;
}

TEST(ContactReduction, SmallPatchesPassThroughUnchanged) {
  std::vector<Contact> cs = {
      contactAt(0, kGround, Vec3(0, 0, 0), Vec3(0.1, 0, 1), 0.01, 1),  // pair (0, ground): one
      contactAt(1, 2, Vec3(1, 0, 0), Vec3(0, 0.2, 1), 0.02, 2),        // pair (1, 2): four
      contactAt(1, 2, Vec3(1, 1, 0), Vec3(0, 0, 1), 0.03, 3),
      contactAt(1, 2, Vec3(2, 0, 0), Vec3(0.3, 0, 1), 0.01, 4),
      contactAt(1, 2, Vec3(2, 1, 0), Vec3(0, 0, 1), 0.02, 5)};
  std::vector<Contact> reduced = cs;
  reduceContacts(reduced);
  ASSERT_EQ(reduced.size(), cs.size());
  // Same contacts; within a pair the deepest comes first.
  EXPECT_TRUE(same(reduced[0], cs[0]));
  EXPECT_TRUE(same(reduced[1], cs[2]));
  for (const Contact& c : cs)
    EXPECT_TRUE(
        std::any_of(reduced.begin(), reduced.end(), [&](const Contact& r) { return same(r, c); }));
}

TEST(ContactReduction, FaceOnTheFloorKeepsTheDeepestAndSpansThePatch) {
  auto s = test::boxShape(0.4, 0.3, 0.2, 800, 4);
  // Slightly tilted so that one corner is deepest, sunk so that a whole face touches.
  const Quat q(Eigen::AngleAxisd(0.01, Vec3(1, 1, 0).normalized()));
  const Collider box = sphereTreeCollider(0, *s->tree, Vec3(0, 0, test::restOffset(*s) - 0.004), q);
  std::vector<Contact> all;
  collide(box, planeCollider(0.0), all);
  ASSERT_GT(all.size(), 50u) << "a face of leaf contacts";
  std::vector<Contact> reduced = all;
  reduceContacts(reduced);
  ASSERT_LE(reduced.size(), static_cast<std::size_t>(kContactsPerPatch));
  auto deepest = [](const std::vector<Contact>& cs) {
    double d = 0;
    for (const Contact& c : cs) d = std::max(d, c.depth);
    return d;
  };
  EXPECT_EQ(deepest(reduced), deepest(all));
  auto extent = [](const std::vector<Contact>& cs) {
    Eigen::AlignedBox2d b;
    for (const Contact& c : cs) b.extend(c.point.head<2>());
    return b;
  };
  // The kept points reach the patch's extremes (to within one leaf-sphere spacing: the
  // corners of the patch are leaf centres, so the same ones).
  const double spacing = s->tree->leaves().edge;
  EXPECT_NEAR(extent(reduced).volume(), extent(all).volume(),
              spacing * (extent(all).sizes().sum()));
  for (const Contact& c : reduced) EXPECT_EQ(c.normal, Vec3::UnitZ());
}

TEST(ContactReduction, PerpendicularPatchesStayApart) {
  std::vector<Contact> cs;
  for (int i = 0; i < 10; ++i) {
    cs.push_back(contactAt(0, 1, Vec3(0.1 * i, 0, 0), Vec3(0, 0.1 * (i % 3 - 1), 1), 0.01, i));
    cs.push_back(contactAt(0, 1, Vec3(0, 0.1 * i, 1), Vec3(1, 0, 0.1 * (i % 3 - 1)), 0.01, 20 + i));
  }
  reduceContacts(cs);
  int up = 0, side = 0;
  for (const Contact& c : cs) {
    up += c.normal.z() > 0.99;
    side += c.normal.x() > 0.99;
  }
  EXPECT_GE(up, 2);
  EXPECT_GE(side, 2);
  EXPECT_EQ(up + side, static_cast<int>(cs.size()));
  EXPECT_LE(cs.size(), 2u * kContactsPerPatch);
}

// Pairs are reduced in place, one after another: reducing a list of several pairs (large and
// small, one with two patches) gives what reducing each pair's contacts alone gives.
TEST(ContactReduction, PairsReducedInPlaceAsIfEachWereAlone) {
  std::vector<std::vector<Contact>> pairs(4);
  std::uint32_t leaf = 0;
  auto wobble = [](int i) { return 0.01 * ((i * 37) % 11 - 5); };
  for (int i = 0; i < 30; ++i)
    pairs[0].push_back(contactAt(0, kGround, Vec3(0.05 * (i % 6), 0.05 * (i / 6), 0),
                                 Vec3(wobble(i), wobble(i + 3), 1), 0.001 * (i % 7), leaf++));
  for (int i = 0; i < 3; ++i)
    pairs[1].push_back(contactAt(0, 1, Vec3(i, 0, 0), Vec3(0, 0, 1), 0.002 * i, leaf++));
  for (int i = 0; i < 50; ++i)  // two patches at 90 degrees, interleaved
    pairs[2].push_back(contactAt(1, 2, Vec3(0.03 * i, 0.01 * (i % 5), 0.02 * (i % 3)),
                                 i % 2 ? Vec3(1, wobble(i), 0) : Vec3(wobble(i), 0, 1),
                                 0.0005 * (i % 9), leaf++));
  pairs[3].push_back(contactAt(2, kGround, Vec3(5, 5, 0), Vec3(0, 0, 1), 0.003, leaf++));
  std::vector<Contact> all, expected;
  for (std::vector<Contact> p : pairs) {
    all.insert(all.end(), p.begin(), p.end());
    reduceContacts(p);
    expected.insert(expected.end(), p.begin(), p.end());
  }
  reduceContacts(all);
  ASSERT_EQ(all.size(), expected.size());
  ASSERT_LT(all.size(), 30u) << "the large pairs were reduced";
  for (std::size_t i = 0; i < all.size(); ++i) EXPECT_TRUE(same(all[i], expected[i])) << i;
}

}  // namespace
}  // namespace vf

// The hierarchical descent of fig. 3 against a brute-force oracle that lives only here: every
// leaf sphere of A against every leaf sphere of B. Invariants checked on random poses:
//   - the descent finds exactly the brute-force leaf pairs (same set, no duplicates);
//   - swapping A and B gives the same pairs with flipped normals;
//   - normals are unit, depths positive and equal to r1 + r2 - |x1 - x2|;
//   - plane contacts are exactly the leaf spheres that cross the plane.
#include "sim/collide/narrow_phase.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>
#include <set>
#include <utility>

#include "sim/collide/polygon_contact.h"
#include "sim/core/prng.h"
#include "sim/shape/convex_polyhedron.h"
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

// The leaf of `l` farthest along `dir` (a box's corner leaf, for the diagonal).
std::uint32_t farthestLeaf(const SphereTreeLevel& l, const Vec3& dir) {
  std::uint32_t best = 0;
  for (std::uint32_t k = 0; k < l.centers.size(); ++k)
    if (l.centers[k].dot(dir) > l.centers[best].dot(dir)) best = k;
  return best;
}

// Two equal boxes at different levels, and the leaves at their (+,+,+) corners: the leaf pair
// whose every ancestor test is as tight as its own when the corners face each other.
class NarrowPhaseCorners : public ::testing::Test {
 protected:
  std::shared_ptr<const Shape> sa = test::boxShape(0.3, 0.3, 0.3, 800, 4);
  std::shared_ptr<const Shape> sb = test::boxShape(0.3, 0.3, 0.3, 800, 3);
  const SphereTreeLevel& la = sa->tree->leaves();
  const SphereTreeLevel& lb = sb->tree->leaves();
  const Vec3 diag = Vec3(1, 1, 1).normalized();
  const std::uint32_t i = farthestLeaf(la, diag), j = farthestLeaf(lb, diag);
};

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

// The descents test inner nodes in body a's frame (and the plane's height in the body frame),
// widened by a slack, and decide leaves in world coordinates. The hard case: a box's corner
// leaf, whose sphere touches every ancestor's sphere at the box corner (circumscribed spheres of
// a corner sub-voxel and its voxel both pass through the corner), turned so that the corner
// diagonal faces the plane or the other box's corner, at touching distance, far from the origin
// (coordinates of tens of km, whose rounding is what differs between the frames): every
// ancestor test then has the leaf's own margin, and an unwidened body-frame test drops contacts
// that the world-frame leaf test keeps. The contacts must be exactly the brute-force ones, with
// the brute-force expressions' values to the bit.
TEST_F(NarrowPhaseCorners, BodyFrameTestsLoseNoLeafPairFarFromTheOriginOrAtTouchingDistance) {
  Prng rng(11);
  int planeHits = 0, pairHits = 0;
  for (int trial = 0; trial < 200; ++trial) {
    const Vec3 far(rng.uniform(2e4, 5e4), rng.uniform(-5e4, -2e4), rng.uniform(1e3, 3e3));
    const Eigen::AngleAxisd twist(rng.uniform(0, 6.28), Vec3::UnitZ());
    // a's corner diagonal straight down, onto the plane through the lowest point of leaf i.
    const Quat qa = Quat(twist) * Quat::FromTwoVectors(diag, -Vec3::UnitZ());
    const Collider a = sphereTreeCollider(0, *sa->tree, far, qa);
    const Vec3 ca = a.x + a.R * la.centers[i];
    const double h = ca.z() - la.radius * (1 - rng.uniform(0, 1e-12));
    std::vector<Contact> onPlane;
    collide(a, planeCollider(h), onPlane);
    std::set<std::uint32_t> planeExpected, planeFound;
    for (std::uint32_t k = 0; k < la.centers.size(); ++k)
      if ((a.x + a.R * la.centers[k]).z() - h < la.radius) planeExpected.insert(k);
    for (const Contact& c : onPlane) {
      planeFound.insert(c.leafA);
      const Vec3 w = a.x + a.R * la.centers[c.leafA];
      EXPECT_EQ(c.depth, la.radius - (w.z() - h));
      EXPECT_EQ(c.point, w - (w.z() - h) * Vec3::UnitZ());
    }
    EXPECT_EQ(planeFound, planeExpected) << "trial " << trial;
    planeHits += planeExpected.count(i) > 0;

    // a's corner diagonal along a random direction u, b's along -u, the two corner leaves at
    // touching distance (a random direction, so that rounding falls either way).
    const Vec3 u = randomRotation(rng) * Vec3::UnitX();
    const Quat qa2 = Quat::FromTwoVectors(diag, u);
    const Quat qb = Quat::FromTwoVectors(diag, -u);
    const Collider a2 = sphereTreeCollider(0, *sa->tree, far, qa2);
    const double r = la.radius + lb.radius;
    const Vec3 ca2 = a2.x + a2.R * la.centers[i];
    const Vec3 xb =
        ca2 + (1 - rng.uniform(0, 1e-12)) * r * u - qb.toRotationMatrix() * lb.centers[j];
    const Collider b = sphereTreeCollider(1, *sb->tree, xb, qb);
    const auto expected = bruteForce(a2, b);
    std::vector<Contact> contacts;
    collide(a2, b, contacts);
    std::set<std::pair<std::uint32_t, std::uint32_t>> found;
    for (const Contact& c : contacts) {
      found.insert({c.leafA, c.leafB});
      const Vec3 wa = a2.x + a2.R * la.centers[c.leafA];
      const Vec3 wb = b.x + b.R * lb.centers[c.leafB];
      EXPECT_EQ(c.point, 0.5 * (wa + wb));
      EXPECT_EQ(c.depth, r - (wa - wb).norm());
    }
    EXPECT_EQ(found, expected) << "trial " << trial;
    pairHits += expected.count({i, j}) > 0;
  }
  // Rounding decides these contacts, so some touch and some do not; both must occur for the
  // test to show anything.
  EXPECT_GT(planeHits, 10);
  EXPECT_LT(planeHits, 190);
  EXPECT_GT(pairHits, 10);
  EXPECT_LT(pairHits, 190);
}

// The body-body descent prunes in single precision (TreeTreeDescent), widened by a bound on
// the float rounding; the candidates are served by a float test too. Near the origin the
// double rounding slack is about 1e-9 m, far below float rounding (about 1e-7 m for bodies of
// this size), so the float widening alone must keep every touching leaf pair. The case where
// every ancestor test is as tight as the leaf test: two box corners facing each other along a
// random direction, the corner leaves overlapping by a random depth of up to 1e-6 of their
// radii (up to 5e-8 m, where float rounding decides an unwidened test), tested by a plain
// descent and by candidates built 0.1 mm back along the same direction and then served. The
// contacts must be exactly the brute-force ones. (Without the float widening this fails, as
// checked: the corner pair goes missing in some trials.)
TEST_F(NarrowPhaseCorners, FloatPruningLosesNoLeafPairAtTouchingDistanceNearTheOrigin) {
  std::vector<BodyInfo> bodies = test::oneBody(sa);
  bodies.push_back(test::oneBody(sb)[0]);
  const double r = la.radius + lb.radius;
  Prng rng(5);
  int descentHits = 0, servedHits = 0;
  for (int trial = 0; trial < 300; ++trial) {
    const Vec3 u = randomRotation(rng) * Vec3::UnitX();
    std::vector<BodyState> states(2);
    states[0].x = Vec3(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1));
    // Turned about u at random, so that the relative pose (and its rounding) differs from
    // trial to trial; the corner diagonals stay along u.
    states[0].q = Quat(Eigen::AngleAxisd(rng.uniform(0, 6.28), u)) * Quat::FromTwoVectors(diag, u);
    states[1].q = Quat(Eigen::AngleAxisd(rng.uniform(0, 6.28), u)) * Quat::FromTwoVectors(diag, -u);
    const Vec3 ca = states[0].x + states[0].q.toRotationMatrix() * la.centers[i];
    const Vec3 xb =
        ca + (1 - rng.uniform(0, 1e-6)) * r * u - states[1].q.toRotationMatrix() * lb.centers[j];
    auto expectBruteForce = [&](const std::vector<Contact>& contacts, const char* how) {
      const Collider a = sphereTreeCollider(0, *sa->tree, states[0].x, states[0].q);
      const Collider b = sphereTreeCollider(1, *sb->tree, states[1].x, states[1].q);
      std::set<std::pair<std::uint32_t, std::uint32_t>> found;
      for (const Contact& c : contacts) found.insert({c.leafA, c.leafB});
      const auto expected = bruteForce(a, b);
      EXPECT_EQ(found, expected) << how << ", trial " << trial;
      return expected.count({i, j}) > 0;
    };
    // A plain descent at the touching pose.
    states[1].x = xb;
    std::vector<Contact> contacts;
    findContacts(bodies, states, {{0, 1}}, std::nullopt, nullptr, nullptr, contacts, nullptr);
    descentHits += expectBruteForce(contacts, "descent");
    // Candidates: a plain descent and a build 0.1 mm back, then served at the touching pose.
    states[1].x = xb - 1e-4 * u;
    CandidateCache cache;
    for (int k = 0; k < 2; ++k) {
      contacts.clear();
      findContacts(bodies, states, {{0, 1}}, std::nullopt, nullptr, nullptr, contacts, &cache);
    }
    states[1].x = xb;
    contacts.clear();
    findContacts(bodies, states, {{0, 1}}, std::nullopt, nullptr, nullptr, contacts, &cache);
    ASSERT_EQ(cache.served, 1u) << "trial " << trial;
    servedHits += expectBruteForce(contacts, "served");
  }
  // The corner pair touches in every trial (by at least the double rounding).
  EXPECT_GT(descentHits, 290);
  EXPECT_GT(servedHits, 290);
}

// A tree of one level (its root is its only leaf, at the body origin; the rock-fall tests' smooth
// balls) against the plane and against another such tree.
TEST(NarrowPhase, OneLevelTreesTouchAtTheirRootLeaf) {
  SphereTree ball;
  SphereTreeLevel leaf;
  leaf.radius = 0.25;
  leaf.edge = 0.5 / std::sqrt(3.0);
  leaf.centers = {Vec3::Zero()};
  leaf.childBegin = {0, 0};
  ball.levels = {leaf};
  finishSphereTree(ball);  // bounding radius 0.25
  const Quat q = Quat(Eigen::AngleAxisd(0.3, Vec3(1, 2, 3).normalized()));
  const Collider a = sphereTreeCollider(0, ball, Vec3(1, 2, 0.2), q);
  std::vector<Contact> contacts;
  collide(a, planeCollider(0.0), contacts);
  ASSERT_EQ(contacts.size(), 1u);
  EXPECT_EQ(contacts[0].point, Vec3(1, 2, 0));
  EXPECT_NEAR(contacts[0].depth, 0.05, 1e-15);
  contacts.clear();
  collide(sphereTreeCollider(0, ball, Vec3(1, 2, 0.3), q), planeCollider(0.0), contacts);
  EXPECT_TRUE(contacts.empty());
  const Collider b = sphereTreeCollider(1, ball, Vec3(1.4, 2, 0.2), q);
  collide(a, b, contacts);
  ASSERT_EQ(contacts.size(), 1u);
  EXPECT_EQ(contacts[0].normal, Vec3(-1, 0, 0));
  EXPECT_NEAR(contacts[0].depth, 0.1, 1e-15);
}

// The same contacts in the same order, bit for bit (so that rounding counts).
::testing::AssertionResult sameContacts(const std::vector<Contact>& plain,
                                        const std::vector<Contact>& served) {
  if (served.size() != plain.size())
    return ::testing::AssertionFailure() << served.size() << " contacts, not " << plain.size();
  for (std::size_t c = 0; c < plain.size(); ++c) {
    const Contact &x = plain[c], &y = served[c];
    if (!(x.a == y.a && x.b == y.b && x.leafA == y.leafA && x.leafB == y.leafB) ||
        std::memcmp(x.point.data(), y.point.data(), sizeof(Vec3)) != 0 ||
        std::memcmp(x.normal.data(), y.normal.data(), sizeof(Vec3)) != 0 ||
        std::memcmp(&x.depth, &y.depth, sizeof(double)) != 0)
      return ::testing::AssertionFailure() << "contact " << c << " differs";
  }
  return ::testing::AssertionSuccess();
}

// Temporal coherence against the terrain (collideTreeHeightfield, PairCandidates) must give
// the plain descent's contacts, bit for bit, where the leaf test is least regular: a box
// walked slowly (so candidates are built and served) and now and then jumped (so they are
// dropped) over a sloping, wavy grid with a NODATA hole, across the hole and past the east
// border, where it meets the border wall, turning as it goes and for a while turning in place
// (it fails, as checked, when the candidates' margin or the rotation's share of the bound on
// how far leaves moved is left out). Oracle: the same call without
// candidates. The walk must have been served by candidates often, and must have met the wall
// and the hole, or the comparison would show little.
TEST(NarrowPhase, TerrainCandidatesGiveThePlainDescentsContactsOverHolesAndBorders) {
  auto surface = [](double x, double y) {
    return 0.15 * x + 0.3 * std::sin(1.3 * x) + 0.2 * std::cos(0.9 * y);
  };
  Heightfield field;
  field.nx = field.ny = 12;
  field.cell = 0.5;
  for (int j = 0; j < field.ny; ++j)
    for (int i = 0; i < field.nx; ++i) field.z.push_back(surface(0.5 * i, 0.5 * j));
  field.z[5 * field.nx + 6] = NAN;  // the four cells around sample (6, 5): a hole at (3, 2.5)
  field.zMin = INFINITY;
  field.zMax = -INFINITY;
  for (double z : field.z)
    if (!std::isnan(z)) field.zMin = std::min(field.zMin, z), field.zMax = std::max(field.zMax, z);

  auto s = test::boxShape(0.3, 0.2, 0.15, 800, 3);
  const std::vector<BodyInfo> bodies = test::oneBody(s);
  std::vector<BodyState> states(1);
  CandidateCache cache;
  Prng rng(11);
  Vec3 at(1.2, 2.4, 0);
  Quat q = Quat::Identity();
  int wallPoses = 0, holePoses = 0, contactPoses = 0;
  const int poses = 9000;
  for (int k = 0; k < poses; ++k) {
    // East at 0.6 mm a pose (past the border at x = 5.5 by the end), drifting in y, turning
    // by 1 mrad; every 100th pose a jump of a few cm; for 1,000 poses a turn in place (2 mrad
    // a pose), where only the rotation bounds how far leaves moved. The box's centre rides 10 cm
    // above the wavy surface's formula, which goes on beyond the grid and over the hole.
    const double jump = k % 100 == 99 ? 0.05 : 0.0;
    const bool turn = k >= 2000 && k < 3000;
    at += Vec3((turn ? 0 : 0.0006) + jump * rng.uniform(-1, 1),
               (turn ? 0 : 0.0001) + jump * rng.uniform(-1, 1), 0);
    q = (q * Quat(Eigen::AngleAxisd((turn ? 0.002 : 0.001) + jump, Vec3(1, 0.5, 0.2).normalized())))
            .normalized();
    states[0].x = Vec3(at.x(), at.y(), surface(at.x(), at.y()) + 0.1);
    states[0].q = q;
    std::vector<Contact> plain, served;
    findContacts(bodies, states, {}, std::nullopt, &field, nullptr, plain, nullptr);
    findContacts(bodies, states, {}, std::nullopt, &field, nullptr, served, &cache);
    ASSERT_TRUE(sameContacts(plain, served)) << "pose " << k;
    contactPoses += !plain.empty();
    wallPoses += std::any_of(plain.begin(), plain.end(),
                             [](const Contact& c) { return c.normal.z() == 0.0; });
    holePoses += std::abs(at.x() - 3.0) < 0.5 && std::abs(at.y() - 2.5) < 0.5;
  }
  EXPECT_GT(contactPoses, poses / 2);
  EXPECT_GT(wallPoses, 20) << "the walk never met the border wall";
  EXPECT_GT(holePoses, 20) << "the walk never crossed the hole";
  EXPECT_GT(cache.served, static_cast<std::uint64_t>(poses / 3)) << "candidates rarely served";
  EXPECT_GT(cache.descents, 20u) << "candidates were never rebuilt";
}

// The candidate cache keeps each body pair's candidates in a slot, and a pair that appears
// takes the slot of one that has gone: it must start afresh there. Here pair (1, 2) takes the
// slot of (0, 1) at the same relative pose, so the old pair's candidates would "hold" for it,
// but body 2 has a finer tree than body 0, whose leaf numbers they are. Oracle: the same
// calls without candidates, bit for bit. Fails, as checked, when a reused slot is not
// restarted.
TEST(NarrowPhase, ABodyPairTakingAFreedSlotStartsAfresh) {
  auto coarse = test::boxShape(0.3, 0.3, 0.3, 800, 3);
  auto fine = test::boxShape(0.3, 0.3, 0.3, 800, 4);
  std::vector<BodyInfo> bodies(3);
  for (int i = 0; i < 3; ++i) {
    bodies[i].shape = i == 2 ? fine : coarse;
    bodies[i].invMass = 1 / bodies[i].shape->mass;
  }
  CandidateCache cache;
  std::vector<BodyState> states(3);
  int compared = 0;
  for (int k = 0; k < 60; ++k) {
    // Faces 2 cm deep in each other, drifting by 0.1 mm a pose; the pair tested alternates
    // every 10 poses.
    const double gap = 0.28 + 1e-4 * (k % 10);
    for (int i = 0; i < 3; ++i) states[i].x = Vec3(gap * i, 0.01 * i, 0);
    const std::vector<BodyPair> pairs = {(k / 10) % 2 == 0 ? BodyPair{0, 1} : BodyPair{1, 2}};
    std::vector<Contact> plain, served;
    findContacts(bodies, states, pairs, std::nullopt, nullptr, nullptr, plain, nullptr);
    findContacts(bodies, states, pairs, std::nullopt, nullptr, nullptr, served, &cache);
    ASSERT_FALSE(plain.empty()) << "pose " << k;
    ASSERT_TRUE(sameContacts(plain, served)) << "pose " << k;
    // (1, 2) follows (0, 1) in key order, so the merge frees (0, 1)'s slot before it meets
    // (1, 2), which takes it.
    if (k == 10) {
      EXPECT_EQ(cache.slots.size(), 1u) << "the pairs did not share a slot";
    }
    ++compared;
  }
  EXPECT_EQ(compared, 60);
  EXPECT_GT(cache.served, 30u) << "candidates rarely served";
}

// Both grounds are body kGround, and a scene may have a floor plane that coincides with the
// terrain (scenes/cliff.toml's plane lies on its valley floor): a leaf (or, with the polygon
// method, a vertex) resting there touches both, and its two contacts must still have keys of
// their own, or the solver's warm start hands both rows one cached impulse. Fails, as checked,
// with the terrain contacts' leafB left at the plane's 0.
TEST(NarrowPhase, PlaneAndTerrainContactsOfOneLeafHaveKeysOfTheirOwn) {
  Heightfield field;  // flat at z = 0, like the plane
  field.nx = field.ny = 5;
  field.cell = 1.0;
  field.z.assign(25, 0.0);
  auto s = test::boxShape(0.4, 0.3, 0.2, 800, 3);
  const std::vector<BodyInfo> bodies = test::oneBody(s);
  std::vector<BodyState> states(1);
  states[0].x = Vec3(2.0, 2.0, 0.1 - 0.005);  // 5 mm into both
  std::vector<Contact> contacts;
  findContacts(bodies, states, {}, 0.0, &field, nullptr, contacts, nullptr);
  auto expectOwnKeys = [](const std::vector<Contact>& found, const char* what) {
    int plane = 0, terrain = 0;
    std::set<ContactKey> keys;
    for (const Contact& c : found) {
      (c.leafB == kTerrainLeaf ? terrain : plane) += 1;
      keys.insert(ContactKey{c.a, c.b, c.leafA, c.leafB});
    }
    EXPECT_GT(plane, 0) << what;
    EXPECT_EQ(plane, terrain) << what << ": the same leaves touch both";
    EXPECT_EQ(keys.size(), found.size()) << what << ": two contacts share a key";
  };
  expectOwnKeys(contacts, "sphere tree");

  const ConvexPolyhedron box = buildConvexPolyhedron(test::boxMesh(0.4, 0.3, 0.2), "box", "test");
  const Collider a = polygonCollider(0, box, states[0].x, Quat::Identity());
  std::vector<Contact> vertices;
  collidePolygonPlane(a, planeCollider(0.0), vertices);
  collidePolygonHeightfield(a, heightfieldCollider(field), vertices);
  expectOwnKeys(vertices, "polygon method");
}

}  // namespace
}  // namespace vf

// Contact reduction (sim/collide/contact_reduction.h):
//   - patches of at most kContactsPerPatch contacts, a single contact in particular, pass
//     through bit for bit (eq. 15 unchanged);
//   - a box face on the floor (a grid of leaf contacts) keeps its deepest contact and contacts
//     spanning the whole patch (the same x and y extent as all leaf contacts);
//   - two patches at 90 degrees (interlocked non-convex bodies) stay apart, each with its own
//     normal;
//   - the shortcuts (a body's plane contacts reduced as they come, or from its candidates'
//     bounds; scans that skip groups of points) choose what the plain reduction of the stored
//     contacts chooses, bit for bit.
// The physics with reduction on (a flat landing rebounds to eps^2 h without tilting, a stack
// rests without creep) is checked by tests/scenario/analytic_test.cpp with the same bounds as
// without reduction.
#include "sim/collide/contact_reduction.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>

#include "sim/collide/broad_phase.h"
#include "sim/collide/narrow_phase.h"
#include "sim/core/prng.h"
#include "sim/core/worker_pool.h"
#include "sim/geometry/mesh_import.h"
#include "sim/shape/shape.h"
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

// Bits, so that rounding counts: the patch and the pair reduction must agree exactly.
bool identical(const Contact& x, const Contact& y) {
  return x.a == y.a && x.b == y.b && x.leafA == y.leafA && x.leafB == y.leafB &&
         std::memcmp(x.point.data(), y.point.data(), sizeof(Vec3)) == 0 &&
         std::memcmp(x.normal.data(), y.normal.data(), sizeof(Vec3)) == 0 &&
         std::memcmp(&x.depth, &y.depth, sizeof(double)) == 0;
}

// PlanePatch (the reduction made while a body's plane contacts are found) must give what
// reducing the stored contacts gives, bit for bit, in the cases where its shortcuts could
// differ: a box lying exactly level (every bottom leaf equally deep: the first must win the
// ties), tilted about two axes (one deepest corner), on an edge, on a corner (a patch of a few
// contacts: kept as they are, deepest first; stable among equal depths, checked by hand), and
// at 20 random poses sunk into the floor. Oracle: reduceContacts on the same contacts.
TEST(ContactReduction, PlanePatchGivesTheStoredContactsReduction) {
  auto s = test::boxShape(0.4, 0.3, 0.2, 800, 4);
  const double rest = test::restOffset(*s);
  struct Pose {
    Quat q;
    double z;
  };
  std::vector<Pose> poses = {
      {Quat::Identity(), rest - 0.003},
      {Quat(Eigen::AngleAxisd(0.01, Vec3(1, 1, 0).normalized())), rest - 0.004},
      {Quat(Eigen::AngleAxisd(0.3, Vec3::UnitX())), 0},               // on an edge
      {Quat(Eigen::AngleAxisd(0.5, Vec3(1, 1, 0).normalized())), 0},  // on a corner
  };
  // Edge and corner poses: lowered until the lowest leaf is just under the floor.
  for (Pose& p : poses)
    if (p.z == 0) {
      const Mat3 R = p.q.toRotationMatrix();
      double low = INFINITY;
      for (const Vec3& c : s->tree->leaves().centers) low = std::min(low, (R * c).z());
      p.z = -low + s->tree->leaves().radius - 1e-4;
    }
  Prng rng(7);
  for (int k = 0; k < 20; ++k)
    poses.push_back(
        {Quat(Eigen::AngleAxisd(rng.uniform(0, 0.4),
                                Vec3(rng.uniform(-1, 1), rng.uniform(-1, 1), 0.2).normalized())),
         rest - rng.uniform(0, 0.01)});
  std::size_t smallPatches = 0, largePatches = 0;
  for (std::size_t k = 0; k < poses.size(); ++k) {
    const Collider box = sphereTreeCollider(3, *s->tree, Vec3(0.1, -0.2, poses[k].z), poses[k].q);
    const Collider floor = planeCollider(0.0);
    std::vector<Contact> all;
    collide(box, floor, all);
    ASSERT_FALSE(all.empty()) << "pose " << k;
    (all.size() <= kContactsPerPatch ? smallPatches : largePatches)++;
    std::vector<Contact> expected = all;
    reduceContacts(expected);
    PlanePatch patch;
    patch.start(floor.normal);
    for (const Contact& c : all) patch.add(c.point, c.depth, c.leafA);
    EXPECT_EQ(patch.size(), all.size());
    std::vector<Contact> got;
    patch.finish(3, kGround, got);
    ASSERT_EQ(got.size(), expected.size()) << "pose " << k;
    for (std::size_t i = 0; i < got.size(); ++i)
      EXPECT_TRUE(identical(got[i], expected[i])) << "pose " << k << ", contact " << i;
  }
  EXPECT_GE(smallPatches, 1u) << "the corner";
  EXPECT_GE(largePatches, 2u);
  // A small patch with equal depths (stable order among them), made by hand.
  std::vector<Contact> few;
  const double depths[] = {0.01, 0.02, 0.02, 0.01};
  for (int i = 0; i < 4; ++i)
    few.push_back(contactAt(5, kGround, Vec3(0.1 * i, 0.05 * i, 0), Vec3::UnitZ(), depths[i],
                            static_cast<std::uint32_t>(10 + i)));
  std::vector<Contact> expected = few;
  reduceContacts(expected);
  PlanePatch patch;
  patch.start(Vec3::UnitZ());
  for (const Contact& c : few) patch.add(c.point, c.depth, c.leafA);
  std::vector<Contact> got;
  patch.finish(5, kGround, got);
  ASSERT_EQ(got.size(), 4u);
  for (std::size_t i = 0; i < got.size(); ++i) EXPECT_TRUE(identical(got[i], expected[i])) << i;
  EXPECT_EQ(got[0].leafA, 11u);
  EXPECT_EQ(got[1].leafA, 12u);
}

// The narrow phase reduces each collider pair as it goes (findContacts with reduce), on its
// worker threads: the result must be the reduction of the unreduced contacts, pair by pair,
// for body-body pairs and bodies on the floor alike, with one thread and with two. A pile of
// boxes resting on the floor and on each other gives both kinds, large patches and small.
TEST(ContactReduction, NarrowPhaseReducesEachPairAsTheStoredContactsWouldBe) {
  auto s = test::boxShape(0.4, 0.3, 0.2, 800, 3);
  const double rest = test::restOffset(*s);
  const int n = 40;
  std::vector<BodyInfo> bodies(n);
  std::vector<BodyState> states(n);
  Prng rng(11);
  for (int i = 0; i < n; ++i) {
    bodies[i].shape = s;
    bodies[i].invMass = 1 / s->mass;
    // Two layers in a row along x: the lower ones on the floor, the upper ones sunk into them.
    const int col = i / 2;
    const bool upper = i % 2 == 1;
    states[i].x = Vec3(0.39 * col, rng.uniform(-0.01, 0.01),
                       rest - 0.002 + (upper ? 0.2 - 0.003 : 0) + rng.uniform(-0.001, 0.001));
    states[i].q = Quat(Eigen::AngleAxisd(
        rng.uniform(0, 0.02), Vec3(rng.uniform(-1, 1), rng.uniform(-1, 1), 1).normalized()));
  }
  std::vector<BodyPair> pairs;
  findPairs(bodies, states, pairs);
  ASSERT_GT(pairs.size(), 20u);
  std::vector<Contact> plain;
  findContacts(bodies, states, pairs, 0.0, nullptr, nullptr, plain);
  std::vector<Contact> expected = plain;
  reduceContacts(expected);
  ASSERT_LT(expected.size(), plain.size() / 4) << "large patches were reduced";
  WorkerPool two(2);
  for (WorkerPool* pool : {static_cast<WorkerPool*>(nullptr), &two}) {
    std::vector<Contact> reduced;
    const ContactCounts counts =
        findContacts(bodies, states, pairs, 0.0, nullptr, pool, reduced, nullptr, true);
    EXPECT_EQ(counts.leafContacts, plain.size());
    ASSERT_EQ(reduced.size(), expected.size());
    for (std::size_t i = 0; i < reduced.size(); ++i)
      EXPECT_TRUE(identical(reduced[i], expected[i])) << i;
  }
}

// A body on the floor whose candidates hold is reduced from them without computing every contact
// (servePlanePatch, served_plane_patch.cpp): from body-frame heights and the bounds of groups of
// candidates, with exact values only where they decide. It must give the reduction of the
// stored contacts bit for bit, step after step, in every case its shortcuts treat apart: a face
// exactly level (every bottom leaf ties for deepest: the first must win), slightly tilted (one
// deepest corner), a group straddling the contact height (leaves decided one by one), a few
// contacts on an edge or corner (kept whole, deepest first), lifted clear (none), 20 km from the
// origin (rounding), for a box and for the non-convex cross, at Lv 4 and 5. Oracle: findContacts
// without candidates or reduction, then reduceContacts. Each pose follows the last by a small
// motion, so the candidates are built and then serve; a jump every 40 steps rebuilds them.
TEST(ContactReduction, ReductionFromPlaneCandidatesGivesTheStoredContactsReduction) {
  const auto cross =
      makeShape("cross", importMesh(std::string(VOXFALL_SOURCE_DIR) + "/scenes/meshes/cross.obj"),
                Vec3::Constant(0.5), 800, 5);
  const std::vector<std::shared_ptr<const Shape>> shapes = {
      test::boxShape(0.4, 0.3, 0.2, 800, 4), test::boxShape(0.5, 0.5, 0.5, 800, 5), cross};
  std::uint64_t served = 0, compared = 0, small = 0, large = 0;
  for (const auto& shape : shapes) {
    const double r = shape->tree->leaves().radius;
    const std::vector<BodyInfo> bodies = test::oneBody(shape);
    std::vector<BodyState> states(1);
    CandidateCache cache;
    Prng rng(31);
    for (int segment = 0; segment < 8; ++segment) {
      // Where the segment starts, and the small motion it makes every step.
      const double far = segment == 5 ? 2e4 : 0.0;
      Vec3 axis(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-0.2, 0.2));
      double tilt = segment == 0 ? 0.0 : rng.uniform(0.001, 0.02);
      if (segment == 6) tilt = 0.5;  // on an edge or a corner: a few contacts
      Quat q(Eigen::AngleAxisd(tilt, axis.normalized()));
      double low = INFINITY;  // the lowest leaf centre below the body origin at this rotation
      for (const Vec3& c : shape->tree->leaves().centers)
        low = std::min(low, (q.toRotationMatrix() * c).z());
      const double sink = segment == 7 ? -0.5 * r : 0.3 * r;  // segment 7 lifts clear
      Vec3 x(far + rng.uniform(-1, 1), rng.uniform(-1, 1), -low + r - sink);
      const Quat turn(
          Eigen::AngleAxisd(segment == 0 ? 0.0 : 2e-5, Vec3(0.3, -0.2, 1).normalized()));
      for (int k = 0; k < 40; ++k) {
        states[0].x = x;
        states[0].q = q;
        const std::uint64_t servedBefore = cache.served;
        std::vector<Contact> got;
        const ContactCounts counts =
            findContacts(bodies, states, {}, 0.0, nullptr, nullptr, got, &cache, true);
        served += cache.served - servedBefore;
        std::vector<Contact> plain;
        findContacts(bodies, states, {}, 0.0, nullptr, nullptr, plain);
        EXPECT_EQ(counts.leafContacts, plain.size()) << segment << " " << k;
        std::vector<Contact> expected = plain;
        reduceContacts(expected);
        ASSERT_EQ(got.size(), expected.size())
            << shape->name << " segment " << segment << " step " << k;
        for (std::size_t i = 0; i < got.size(); ++i)
          ASSERT_TRUE(identical(got[i], expected[i]))
              << shape->name << " segment " << segment << " step " << k << ", contact " << i;
        ++compared;
        (plain.size() > static_cast<std::size_t>(kContactsPerPatch) ? large : small)++;
        // The next pose: a small turn and a drift of a hundredth of a leaf radius, in height
        // up and down so that leaves cross the contact height.
        q = (turn * q).normalized();
        x += Vec3(0.004 * r, -0.003 * r, (k % 20 < 10 ? 0.01 : -0.01) * r);
      }
    }
  }
  // Most tests were served by the candidates, with patches of every size.
  EXPECT_GT(served, compared / 2);
  EXPECT_GT(large, compared / 2);
  EXPECT_GT(small, 20u);
}

// The representatives of one patch (contacts of one pair, all within 60 degrees of the first's
// normal, more than kContactsPerPatch of them) by the reduction's definition, scanning every
// point four times: the oracle for contact_reduction.cpp, which skips groups of points that
// cannot win a scan.
std::vector<Contact> plainReduction(const std::vector<Contact>& cs) {
  // The patch normal: the contacts' common normal when they all carry the same one, else the
  // normalised depth-weighted sum of their normals.
  Vec3 sum = Vec3::Zero();
  bool common = true;
  for (const Contact& c : cs) {
    sum += std::max(c.depth, 0.0) * c.normal;
    common = common && c.normal == cs[0].normal;
  }
  const Vec3 n = common || sum.norm() == 0 ? cs[0].normal : Vec3(sum.normalized());
  const Vec3 t1 = (std::abs(n.x()) < 0.57 ? Vec3::UnitX() : Vec3::UnitY()).cross(n).normalized();
  const Vec3 t2 = n.cross(t1);
  const std::size_t m = cs.size();
  std::vector<Eigen::Vector2d> q(m);
  std::size_t deepest = 0;
  for (std::size_t k = 0; k < m; ++k) {
    q[k] = Eigen::Vector2d(cs[k].point.dot(t1), cs[k].point.dot(t2));
    if (cs[k].depth > cs[deepest].depth) deepest = k;
  }
  auto cross = [](const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
    return a.x() * b.y() - a.y() * b.x();
  };
  std::vector<std::size_t> keep = {deepest};
  auto best = [&](auto score) {
    std::size_t arg = m;
    double top = 0;
    for (std::size_t k = 0; k < m; ++k)
      if (score(q[k]) > top && std::find(keep.begin(), keep.end(), k) == keep.end())
        top = score(q[k]), arg = k;
    return arg;
  };
  const Eigen::Vector2d p0 = q[deepest];
  const std::size_t i1 = best([&](const Eigen::Vector2d& p) { return (p - p0).squaredNorm(); });
  if (i1 < m) {
    keep.push_back(i1);
    const Eigen::Vector2d p1 = q[i1];
    const std::size_t i2 =
        best([&](const Eigen::Vector2d& p) { return std::abs(cross(p1 - p0, p - p0)); });
    if (i2 < m) {
      keep.push_back(i2);
      const Eigen::Vector2d p2 = q[i2];
      const double side = cross(p1 - p0, p2 - p0) > 0 ? 1.0 : -1.0;
      const std::size_t i3 = best([&](const Eigen::Vector2d& p) {
        return -side * std::min(std::min(cross(p1 - p0, p - p0), cross(p2 - p1, p - p1)),
                                cross(p0 - p2, p - p2));
      });
      if (i3 < m) keep.push_back(i3);
    }
  }
  std::vector<Contact> out;
  for (std::size_t k : keep) {
    out.push_back(cs[k]);
    out.back().normal = n;
  }
  return out;
}

// The reduction's scans skip groups of points whose bounding box proves that none of them
// beats the best so far; that must never change the choice. 300 random patches against the
// plain four scans, bit for bit: regular grids (ties everywhere: equal distances, equal
// areas, equal depths) in row order and shuffled, scattered points, points on a circle (every
// one equally far from its centre), with normals tilted up to 40 degrees, 5 to 600 points.
TEST(ContactReduction, PrunedScansChooseWhatThePlainScansChoose) {
  Prng rng(2026);
  int compared[3] = {0, 0, 0};  // patches of each kind with more than kContactsPerPatch points
  for (int trial = 0; trial < 300; ++trial) {
    const Vec3 n =
        Vec3(rng.uniform(-0.6, 0.6), rng.uniform(-0.6, 0.6), 1).normalized();  // <= 40 deg
    const Vec3 u = n.unitOrthogonal(), v = n.cross(u);
    const int kind = trial % 3;
    std::vector<Vec3> pts;
    if (kind == 0) {  // a grid, as a face's leaves lie
      const int nx = 2 + static_cast<int>(rng.uniform(0, 24)),
                ny = 3 + static_cast<int>(rng.uniform(0, 24));
      for (int j = 0; j < ny; ++j)
        for (int i = 0; i < nx; ++i) pts.push_back(Vec3(1, 2, 3) + 0.02 * i * u + 0.02 * j * v);
    } else if (kind == 1) {  // scattered
      const int count = 5 + static_cast<int>(rng.uniform(0, 400));
      for (int i = 0; i < count; ++i)
        pts.push_back(rng.uniform(-0.5, 0.5) * u + rng.uniform(-0.2, 0.2) * v);
    } else {  // on a circle, and its centre
      const int count = 5 + static_cast<int>(rng.uniform(0, 64));
      for (int i = 0; i < count; ++i) {
        const double a = 2 * M_PI * i / count;
        pts.push_back(0.3 * std::cos(a) * u + 0.3 * std::sin(a) * v);
      }
      pts.push_back(Vec3::Zero());
    }
    if (trial % 2 == 1)  // shuffled: groups of consecutive points are then spread out
      for (std::size_t i = pts.size() - 1; i > 0; --i)
        std::swap(pts[i],
                  pts[static_cast<std::size_t>(rng.uniform(0, static_cast<double>(i + 1)))]);
    std::vector<Contact> cs;
    for (std::size_t i = 0; i < pts.size(); ++i) {
      // Depths from a few values (ties), the circle's centre deepest.
      const double depth =
          kind == 2 && pts[i] == Vec3::Zero() ? 0.01 : 0.001 * static_cast<int>(rng.uniform(1, 4));
      cs.push_back(contactAt(0, kGround, pts[i], n, depth, static_cast<std::uint32_t>(i)));
    }
    if (cs.size() <= static_cast<std::size_t>(kContactsPerPatch)) continue;
    ++compared[kind];
    const std::vector<Contact> expected = plainReduction(cs);
    std::vector<Contact> got = cs;
    reduceContacts(got);
    ASSERT_EQ(got.size(), expected.size()) << "trial " << trial;
    for (std::size_t i = 0; i < got.size(); ++i)
      ASSERT_TRUE(identical(got[i], expected[i])) << "trial " << trial << ", contact " << i;
  }
  // Every kind was exercised with patches large enough to be reduced.
  for (int kind = 0; kind < 3; ++kind) EXPECT_GE(compared[kind], 90) << "kind " << kind;
}

}  // namespace
}  // namespace vf

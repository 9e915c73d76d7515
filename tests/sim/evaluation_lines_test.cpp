// Evaluation lines in plan: where a centre-of-mass segment crosses a polyline (worked by hand),
// and the per-line statistics against a hand count and the nearest-rank definition.
#include "sim/ground/evaluation_lines.h"

#include <gtest/gtest.h>

#include <cmath>

namespace vf {
namespace {

const std::vector<std::array<double, 2>> kBent = {{0, 0}, {0, 10}, {10, 10}};  // up, then east

std::vector<CurtainHit> hits(const Vec3& a, const Vec3& b) {
  std::vector<CurtainHit> out;
  curtainHits(kBent, a, b, out);
  return out;
}

TEST(CurtainHits, FractionAndDirectionOfACrossing) {
  // (-1, 5) -> (3, 5) meets x = 0 a quarter of the way, from the line's left (west of a line
  // running north) to its right.
  const auto h = hits(Vec3(-1, 5, 7), Vec3(3, 5, 2));
  ASSERT_EQ(h.size(), 1u);
  EXPECT_DOUBLE_EQ(h[0].s, 0.25);
  EXPECT_EQ(h[0].direction, 1);
  const auto back = hits(Vec3(3, 5, 0), Vec3(-1, 5, 0));
  ASSERT_EQ(back.size(), 1u);
  EXPECT_DOUBLE_EQ(back[0].s, 0.75);
  EXPECT_EQ(back[0].direction, -1);
}

TEST(CurtainHits, AVertexCountsOnceAndTheEndsOnce) {
  // Through the bend (0, 10) diagonally: one crossing, not one per segment.
  EXPECT_EQ(hits(Vec3(-1, 11, 0), Vec3(1, 9, 0)).size(), 1u);
  // Through the last vertex (10, 10) itself: counted.
  EXPECT_EQ(hits(Vec3(10, 11, 0), Vec3(10, 9, 0)).size(), 1u);
  // A segment ending on the line counts; the next one, starting there, does not.
  EXPECT_EQ(hits(Vec3(-1, 5, 0), Vec3(0, 5, 0)).size(), 1u);
  EXPECT_EQ(hits(Vec3(0, 5, 0), Vec3(1, 5, 0)).size(), 0u);
}

TEST(CurtainHits, MissesParallelAndBeyondTheEnds) {
  EXPECT_TRUE(hits(Vec3(1, 0, 0), Vec3(1, 9, 0)).empty());     // parallel to the first segment
  EXPECT_TRUE(hits(Vec3(-1, -1, 0), Vec3(1, -1, 0)).empty());  // below its first vertex
  EXPECT_TRUE(hits(Vec3(11, 9, 0), Vec3(11, 11, 0)).empty());  // past its last vertex
  EXPECT_TRUE(hits(Vec3(-1, 5, 0), Vec3(-1, 5, 0)).empty());   // a rock at rest
}

TEST(SummariseLines, CountsProbabilityAndNearestRankPercentiles) {
  std::vector<EvaluationLine> lines = {{"a", kBent}, {"b", kBent}};
  std::vector<LineCrossing> c;
  // Line 0: rocks 3 (twice) and 5; energies 1..20 kJ over 20 crossings; heights 0.1..2.0 m.
  for (int k = 1; k <= 20; ++k) {
    LineCrossing x;
    x.line = 0;
    x.rock = k < 15 ? 3 : 5;
    x.translationalEnergy = 1000.0 * k - 100;
    x.rotationalEnergy = 100;
    x.height = 0.1 * (21 - k);
    c.push_back(x);
  }
  const auto s = summariseLines(lines, c, 8);
  ASSERT_EQ(s.size(), 2u);
  EXPECT_EQ(s[0].crossings, 20);
  EXPECT_EQ(s[0].rocksCrossing, 2);
  EXPECT_DOUBLE_EQ(s[0].probability, 0.25);
  // Nearest rank over 20 sorted values: p50 -> 10th, p95 -> 19th, p99 -> 20th.
  EXPECT_DOUBLE_EQ(s[0].energy[0], 10000);
  EXPECT_DOUBLE_EQ(s[0].energy[1], 19000);
  EXPECT_DOUBLE_EQ(s[0].energy[2], 20000);
  EXPECT_NEAR(s[0].height[0], 1.0, 1e-12);
  EXPECT_NEAR(s[0].height[1], 1.9, 1e-12);
  EXPECT_NEAR(s[0].height[2], 2.0, 1e-12);
  EXPECT_EQ(s[1].crossings, 0);
  EXPECT_EQ(s[1].probability, 0);
  EXPECT_TRUE(std::isnan(s[1].energy[1]) && std::isnan(s[1].height[1]));
}

}  // namespace
}  // namespace vf

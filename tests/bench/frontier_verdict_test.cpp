// The frontier goal's oracle (bullet_compare --frontier): on hand-made frontiers whose verdicts
// follow from the definition by inspection.
#include "tests/bench/frontier_verdict.h"

#include <gtest/gtest.h>

#include <string>

namespace vf::bench {
namespace {

// The verdict at one Bullet point matched by the voxfall point `setting`.
void expectMatched(const PointVerdict& v, const std::string& setting, double ratio, bool pass) {
  EXPECT_TRUE(v.matched);
  EXPECT_EQ(v.voxfall.setting, setting);
  EXPECT_DOUBLE_EQ(v.ratio, ratio);
  EXPECT_EQ(v.pass, pass);
}

TEST(FrontierVerdict, PassesWhenAShallowerSettingTakesHalfOrLess) {
  // "cheap" is the cheapest voxfall point but deeper than both Bullet points: it must not
  // count. At 50 mm "lv3" is the cheapest of the rest (4 <= 0.5 x 10). At 10 mm "lv4" (as
  // deep as Bullet, so at least as accurate) and "lv5" qualify, and "lv5" is the cheaper
  // (15 <= 0.5 x 40).
  const std::vector<FrontierPoint> voxfall{
      {"cheap", 3, 80}, {"lv3", 4, 30}, {"lv4", 25, 10}, {"lv5", 15, 2}};
  const std::vector<FrontierPoint> bullet{{"1/60 s", 10, 50}, {"1/240 s", 40, 10}};
  const std::vector<PointVerdict> v = frontierVerdict(voxfall, bullet, 0.5);
  ASSERT_EQ(v.size(), 2u);
  expectMatched(v[0], "lv3", 0.4, true);
  expectMatched(v[1], "lv5", 0.375, true);
  EXPECT_TRUE(goalMet(v));
}

TEST(FrontierVerdict, ExactlyHalfPassesAndEqualDepthCounts) {
  const std::vector<PointVerdict> v = frontierVerdict({{"lv4", 5, 20}}, {{"1/60 s", 10, 20}}, 0.5);
  ASSERT_EQ(v.size(), 1u);
  expectMatched(v[0], "lv4", 0.5, true);
}

TEST(FrontierVerdict, FailsWhenTooSlowOrNeverAsAccurate) {
  // At 50 mm the only voxfall point as accurate takes 6 ms against Bullet's 10 (0.6 > 0.5);
  // at 0.5 mm no voxfall point is as shallow: both fail, and so does the goal, though the
  // cheap deep point would pass on time alone.
  const std::vector<FrontierPoint> voxfall{{"cheap", 1, 60}, {"lv4", 6, 5}};
  const std::vector<FrontierPoint> bullet{{"1/60 s", 10, 50}, {"1/960 s", 200, 0.5}};
  const std::vector<PointVerdict> v = frontierVerdict(voxfall, bullet, 0.5);
  ASSERT_EQ(v.size(), 2u);
  expectMatched(v[0], "lv4", 0.6, false);
  EXPECT_FALSE(v[1].matched);
  EXPECT_FALSE(v[1].pass);
  EXPECT_FALSE(goalMet(v));
}

TEST(FrontierVerdict, NoBulletPointsIsNoEvidence) {
  EXPECT_FALSE(goalMet(frontierVerdict({{"lv4", 1, 0}}, {}, 0.5)));
}

}  // namespace
}  // namespace vf::bench

// The forest's edge on maps: the sides of the cells where stems meet no stems, worked out by
// hand on small stands, joined along rows and columns.
#include "sim/ground/forest_outline.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <memory>

#include "sim/ground/forest.h"
#include "sim/shape/heightfield.h"

namespace vf {
namespace {

using Segment = std::array<std::array<double, 2>, 2>;

// A 4 x 3 grid with sample (0, 0) at (10, 20) and 2 m cells; `stands` lists the samples with
// stems.
Forest stand(const std::vector<std::pair<int, int>>& stands) {
  auto g = std::make_shared<Heightfield>();
  g->nx = 4, g->ny = 3, g->x0 = 10, g->y0 = 20, g->cell = 2;
  g->z.assign(12, 0.0);
  Forest f;
  f.grid = g;
  f.density.assign(12, 0.0);
  f.dbh.assign(12, 30.0);
  for (auto [i, j] : stands) f.density[static_cast<std::size_t>(j) * 4 + i] = 400;
  return f;
}

TEST(ForestOutline, ABlockOfTwoCellsIsFourJoinedSides) {
  // Samples (1, 1) and (2, 1): cells x 11..15, y 21..23.
  const std::vector<Segment> expected = {
      {{{11, 21}, {15, 21}}},
      {{{11, 23}, {15, 23}}},  // south and north, row by row
      {{{11, 21}, {11, 23}}},
      {{{15, 21}, {15, 23}}},  // west and east, column by column
  };
  EXPECT_EQ(forestOutline(stand({{1, 1}, {2, 1}})), expected);
}

TEST(ForestOutline, TheGridsBorderClosesAStandThatReachesIt) {
  // Sample (0, 0) alone: its cell x 9..11, y 19..21, two sides on the grid's border.
  const std::vector<Segment> expected = {
      {{{9, 19}, {11, 19}}}, {{{9, 21}, {11, 21}}}, {{{9, 19}, {9, 21}}}, {{{11, 19}, {11, 21}}}};
  EXPECT_EQ(forestOutline(stand({{0, 0}})), expected);
}

TEST(ForestOutline, NoStemsNoEdge) { EXPECT_TRUE(forestOutline(stand({})).empty()); }

}  // namespace
}  // namespace vf

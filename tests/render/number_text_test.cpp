// The numbers of the tables voxfall writes to read back bit-exact (render/output/number_text.h):
// the shortest text that strtod reads back to the same bits, checked against strtod and printf's
// %.17g.
#include "render/output/number_text.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <random>
#include <string>

namespace {

using vf::csvRow;
using vf::numberText;

TEST(NumberText, DecimalValuesReadAsTheyWereWritten) {
  EXPECT_EQ(numberText(0.15), "0.15");  // %.17g: 0.14999999999999999
  EXPECT_EQ(numberText(0.05), "0.05");  // %.17g: 0.050000000000000003
  EXPECT_EQ(numberText(500.0), "500");
  EXPECT_EQ(numberText(-5.0), "-5");
  EXPECT_EQ(numberText(-0.0), "-0");
  // Where no shorter text gives the same double, all 17 digits.
  EXPECT_EQ(numberText(0.1 + 0.2), "0.30000000000000004");
  EXPECT_EQ(numberText(std::numeric_limits<double>::denorm_min()), "5e-324");
  EXPECT_EQ(numberText(std::numeric_limits<double>::infinity()), "inf");
  EXPECT_EQ(numberText(-std::numeric_limits<double>::infinity()), "-inf");
  EXPECT_EQ(numberText(std::numeric_limits<double>::quiet_NaN()), "nan");
  EXPECT_EQ(numberText(std::int64_t{-1234567890123}), "-1234567890123");
}

// Random bit patterns (every finite double is as likely as its pattern): strtod reads each text
// back to the same bits, and the text is never longer than %.17g's.
TEST(NumberText, EveryFiniteDoubleReadsBackToItsBitsInNoMoreCharactersThanPercent17g) {
  std::mt19937_64 bits(20031);
  int checked = 0;
  while (checked < 200000) {
    const std::uint64_t b = bits();
    double x;
    std::memcpy(&x, &b, sizeof x);
    if (!std::isfinite(x)) continue;
    const std::string text = numberText(x);
    const double back = std::strtod(text.c_str(), nullptr);
    std::uint64_t backBits;
    std::memcpy(&backBits, &back, sizeof back);
    ASSERT_EQ(backBits, b) << text;
    char printf17[40];
    std::snprintf(printf17, sizeof printf17, "%.17g", x);
    ASSERT_LE(text.size(), std::strlen(printf17)) << text << " vs " << printf17;
    ++checked;
  }
}

TEST(NumberText, ACsvRowIsItsNumbersSeparatedByCommas) {
  EXPECT_EQ(csvRow(3, 0.5, -2.0, std::int64_t{7}), "3,0.5,-2,7\n");
  EXPECT_EQ(csvRow(0.1), "0.1\n");
}

}  // namespace

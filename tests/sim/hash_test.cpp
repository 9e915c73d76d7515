// Hasher (sim/core/hash.h): the checksum must tell apart states that differ in any bit, and
// must not tell apart +0.0 and -0.0 (the same state).
#include "sim/core/hash.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <vector>

namespace vf {
namespace {

std::uint64_t hashOf(const std::vector<double>& values) {
  Hasher h;
  for (double v : values) h.add(v);
  return h.value();
}

double flipBit(double v, int bit) {
  std::uint64_t u;
  std::memcpy(&u, &v, sizeof u);
  u ^= std::uint64_t{1} << bit;
  std::memcpy(&v, &u, sizeof v);
  return v;
}

// A body's 13 state values (position, quaternion, momenta), as World::stateHash adds them.
const std::vector<double> kState = {1.5, -2.25, 0.125, 0.9,  0.1,   -0.3, 0.3,
                                    4.0, -1.0,  2.5,   0.01, -0.02, 0.03};

TEST(Hasher, SignedZerosHashAlike) {
  std::vector<double> a = kState, b = kState;
  a[4] = 0.0;
  b[4] = -0.0;
  EXPECT_EQ(hashOf(a), hashOf(b));
}

TEST(Hasher, EveryBitOfEveryValueChangesTheHash) {
  const std::uint64_t base = hashOf(kState);
  for (std::size_t i = 0; i < kState.size(); ++i)
    for (int bit = 0; bit < 64; ++bit) {
      std::vector<double> s = kState;
      s[i] = flipBit(s[i], bit);
      if (s[i] == 0.0) continue;  // -0.0 from +0.0's sign bit: the same state by design
      EXPECT_NE(hashOf(s), base) << "value " << i << ", bit " << bit;
    }
}

// Structured differences in two values must not cancel. Plain FNV over whole words,
// h = (h ^ w) * p, fails this: a flipped sign bit stays the top bit of h through every
// multiply by an odd p, so two sign flips cancel exactly (checked below on that fold, so the
// test is known to catch it).
TEST(Hasher, TwoSignFlipsDoNotCancel) {
  auto plainFnvWords = [](const std::vector<double>& values) {
    std::uint64_t h = 0xcbf29ce484222325ull;
    for (double v : values) {
      std::uint64_t u;
      std::memcpy(&u, &v, sizeof u);
      h = (h ^ u) * 0x100000001b3ull;
    }
    return h;
  };
  std::vector<double> flipped = kState;
  flipped[7] = -flipped[7];
  flipped[8] = -flipped[8];
  EXPECT_EQ(plainFnvWords(flipped), plainFnvWords(kState));  // the weakness the scramble fixes
  for (std::size_t i = 0; i < kState.size(); ++i)
    for (std::size_t j = i + 1; j < kState.size(); ++j) {
      std::vector<double> s = kState;
      s[i] = -s[i];
      s[j] = -s[j];
      EXPECT_NE(hashOf(s), hashOf(kState)) << "values " << i << " and " << j;
    }
}

}  // namespace
}  // namespace vf

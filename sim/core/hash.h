// A 64-bit hash over the exact bits of doubles: two states hash equal only if they are
// bit-identical (up to the 2^-64 chance of a collision). Used for World::stateHash() and the
// trajectory checksum.
//
// Each 64-bit word is first scrambled on its own (splitmix64's finaliser, a bijection whose
// every output bit depends on every input bit), then folded in FNV style: h = (h ^ word) * p.
// The fold is a bijection of h for a given word, so a difference in one word always reaches
// the result; the scrambling keeps structured differences in several words (two signs flipped
// together, say) from cancelling. The scrambles do not depend on h, so the processor overlaps
// them, and the chain is one xor and one multiply per word. A byte-by-byte FNV-1a (a chain of
// 112 dependent multiplies per body, serial at the end of every step) takes 3.2 % of the
// samples of a 1,000-rock run, this hash 0.5 %. The choice of hash sets every checksum but no
// trajectory (the hash is only reported, never fed back).
#pragma once

#include <cstdint>
#include <cstring>

namespace vf {

class Hasher {
 public:
  void add(std::uint64_t v) { h_ = (h_ ^ scramble(v)) * 0x100000001b3ull; }
  void add(double v) {
    if (v == 0.0) v = 0.0;  // -0.0 and +0.0 describe the same state
    std::uint64_t bits;
    std::memcpy(&bits, &v, sizeof bits);
    add(bits);
  }
  std::uint64_t value() const { return h_; }

 private:
  static std::uint64_t scramble(std::uint64_t z) {
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
  }
  std::uint64_t h_ = 0xcbf29ce484222325ull;
};

}  // namespace vf

// A 64-bit FNV-1a hash over the exact bytes of doubles: two states hash equal only if they are
// bit-identical. Used for World::stateHash() and the trajectory checksum.
#pragma once

#include <cstdint>
#include <cstring>

namespace vf {

class Hasher {
 public:
  void addBytes(const void* data, std::size_t n) {
    const auto* p = static_cast<const unsigned char*>(data);
    for (std::size_t i = 0; i < n; ++i) {
      h_ ^= p[i];
      h_ *= 0x100000001b3ull;
    }
  }
  void add(double v) {
    if (v == 0.0) v = 0.0;  // -0.0 and +0.0 describe the same state
    addBytes(&v, sizeof v);
  }
  void add(std::uint64_t v) { addBytes(&v, sizeof v); }
  std::uint64_t value() const { return h_; }

 private:
  std::uint64_t h_ = 0xcbf29ce484222325ull;
};

}  // namespace vf

// Fuzz target: the bake reader that `render BAKE` and `export BAKE` use (readBake). Any input
// must load or throw InputError; a loaded bake must answer states at any time, before, inside
// and after its records, without a crash.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "sim/bake.h"
#include "sim/core/error.h"
#include "tests/fuzz/fuzz_input_file.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = vf::fuzz::writeInput("run.bake", data, size);
  try {
    const vf::Bake bake = vf::readBake(path);
    const double end = bake.records.back().time;
    std::vector<char> active;
    for (const double t : {-1.0, 0.0, 0.5 * end, end, end + 1.0}) (void)bake.statesAt(t, active);
  } catch (const vf::InputError&) {
  }
  return 0;
}

// Fuzz target: the terrain reader a scene uses (loadDem: the strict ESRI ASCII check, then GDAL).
// Any input must load or throw InputError; a loaded grid must answer height queries anywhere
// without a crash.
#include <cstddef>
#include <cstdint>

#include "sim/core/error.h"
#include "sim/shape/heightfield.h"
#include "tests/fuzz/fuzz_input_file.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = vf::fuzz::writeInput("terrain.asc", data, size);
  try {
    const vf::Heightfield h = vf::loadDem(path);
    // Queries at the corners, the centre and outside the grid.
    const double w = h.cell * (h.nx - 1), d = h.cell * (h.ny - 1);
    for (double fx : {-0.5, 0.0, 0.5, 1.0, 1.5})
      for (double fy : {-0.5, 0.0, 0.5, 1.0, 1.5}) {
        const double x = h.x0 + fx * w, y = h.y0 + fy * d;
        (void)h.heightAt(x, y);
        (void)h.normalAt(x, y);
        (void)h.maxHeightNear(x, y, h.cell);
      }
  } catch (const vf::InputError&) {
  }
  return 0;
}

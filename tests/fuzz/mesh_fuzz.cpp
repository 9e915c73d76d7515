// Fuzz target: the mesh importer and the closed-mesh checks (importMesh + validateClosedMesh),
// built once per format: VOXFALL_FUZZ_EXT is the file extension (".obj", ".stl", ".ply") that
// tells assimp which reader to use. Any input must load or throw InputError.
#include <cstddef>
#include <cstdint>

#include "sim/core/error.h"
#include "sim/geometry/mesh_checks.h"
#include "sim/geometry/mesh_import.h"
#include "tests/fuzz/fuzz_input_file.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = vf::fuzz::writeInput("mesh" VOXFALL_FUZZ_EXT, data, size);
  try {
    vf::TriMesh mesh = vf::importMesh(path);
    vf::validateClosedMesh(mesh, path);
  } catch (const vf::InputError&) {
  }
  return 0;
}

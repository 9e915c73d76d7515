// Fuzz target: the scene parser (loadScene). Any input must either load or throw InputError;
// a crash, a sanitizer report, a hang or any other exception is a bug. The input file sits next
// to links to the shipped meshes/ and terrain/ folders, so scenes that name them get past the
// file checks into the rest of the parser.
#include <cstddef>
#include <cstdint>
#include <filesystem>

#include "sim/core/error.h"
#include "sim/scene/scene.h"
#include "tests/fuzz/fuzz_input_file.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const bool linked = [] {
    const std::filesystem::path scenes = std::filesystem::path(VOXFALL_SOURCE_DIR) / "scenes";
    std::error_code ec;
    std::filesystem::create_directory_symlink(scenes / "meshes", vf::fuzz::tempFolder() + "/meshes",
                                              ec);
    std::filesystem::create_directory_symlink(scenes / "terrain",
                                              vf::fuzz::tempFolder() + "/terrain", ec);
    return true;
  }();
  (void)linked;
  const std::string path = vf::fuzz::writeInput("scene.toml", data, size);
  try {
    vf::loadScene(path);
  } catch (const vf::InputError&) {
  }
  return 0;
}

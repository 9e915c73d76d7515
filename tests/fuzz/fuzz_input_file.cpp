#include "tests/fuzz/fuzz_input_file.h"

#include <cstdio>
#include <cstdlib>
#include <filesystem>

namespace vf::fuzz {

const std::string& tempFolder() {
  // Never destroyed: the exit handler that removes the folder runs after static destructors.
  static const std::string* folder = [] {
    std::string pattern = (std::filesystem::temp_directory_path() / "voxfall-fuzz-XXXXXX").string();
    if (mkdtemp(pattern.data()) == nullptr) std::abort();
    std::atexit([] {
      std::error_code ec;
      std::filesystem::remove_all(tempFolder(), ec);
    });
    return new std::string(pattern);
  }();
  return *folder;
}

std::string writeInput(const std::string& name, const std::uint8_t* data, std::size_t size) {
  const std::string path = tempFolder() + "/" + name;
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (f == nullptr) std::abort();
  if (size > 0 && std::fwrite(data, 1, size, f) != size) std::abort();
  std::fclose(f);
  return path;
}

}  // namespace vf::fuzz

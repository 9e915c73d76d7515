// libFuzzer harness helper: voxfall's readers take file paths (so that errors can name the
// file), so each fuzz input is written to a file in a private temporary folder first.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

namespace vf::fuzz {

// The process's temporary folder (created on first use, removed at exit).
const std::string& tempFolder();
// Writes the input to tempFolder()/name and returns the path.
std::string writeInput(const std::string& name, const std::uint8_t* data, std::size_t size);

}  // namespace vf::fuzz

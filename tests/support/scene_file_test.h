// A test fixture for scene files: a scratch folder per test with the example cube mesh in it,
// scenes written there, and the check that loading one fails where and as a user would be told.
// The expected position is found by searching the scene text, independently of the loader.
#pragma once

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <utility>

#include "sim/core/error.h"
#include "sim/scene/scene.h"

namespace vf::test {

class SceneFileTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = std::filesystem::temp_directory_path() /
           ("voxfall_scene_test_" + std::to_string(::getpid()) + "_" + info->name());
    std::filesystem::remove_all(dir_);
    std::filesystem::create_directories(dir_);
    std::filesystem::copy_file(std::string(VOXFALL_SOURCE_DIR) + "/scenes/meshes/cube.obj",
                               dir_ / "cube.obj");
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }

  std::string write(const std::string& name, const std::string& text) {
    const std::filesystem::path p = dir_ / name;
    std::filesystem::create_directories(p.parent_path());
    std::ofstream(p) << text;
    return p.string();
  }

  // 1-based line and column of the first occurrence of `needle` in `text`.
  static std::pair<int, int> positionOf(const std::string& text, const std::string& needle) {
    const auto at = text.find(needle);
    EXPECT_NE(at, std::string::npos) << "test bug: '" << needle << "' not in the scene text";
    int line = 1, column = 1;
    for (std::size_t i = 0; i < at; ++i) {
      if (text[i] == '\n') {
        ++line;
        column = 1;
      } else {
        ++column;
      }
    }
    return {line, column};
  }

  // Loading `text` must fail at the first occurrence of `needle` with a message containing
  // `message`.
  void expectError(const std::string& text, const std::string& needle, const std::string& message) {
    const std::string path = write("scene.toml", text);
    const auto [line, column] = positionOf(text, needle);
    try {
      loadScene(path);
      ADD_FAILURE() << "no error; expected '" << message << "' at '" << needle << "'";
    } catch (const InputError& e) {
      EXPECT_EQ(e.where(), path + ":" + std::to_string(line) + ":" + std::to_string(column))
          << e.what();
      EXPECT_NE(e.message().find(message), std::string::npos)
          << "message: " << e.message() << "\nexpected to contain: " << message;
    }
  }

  std::filesystem::path dir_;
};

}  // namespace vf::test

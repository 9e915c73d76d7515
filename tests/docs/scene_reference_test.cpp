// The scene reference (docs/scene-format.md) against the scene loader, in both directions:
// every key the loader accepts is documented and every documented key is accepted (the
// loader's key lists are sim/scene/scene_keys.h, the same lists it refuses other keys with),
// and every complete scene the reference shows (a ```toml scene block) loads.
//
// The reference's convention: a heading that names tables in backticks (`[simulation]`,
// `[[bodies]]`, `[shapes.NAME]`, several in one heading when they share keys) is followed by a
// table whose rows start with a key in backticks; keys of inline tables and arrays of tables
// are dotted paths (`rest.speed`, `path.time`). Each oracle is itself shown to report a
// missing key, an extra key and a scene that does not load.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "sim/core/error.h"
#include "sim/scene/scene.h"
#include "sim/scene/scene_keys.h"
#include "tests/support/voxfall_command.h"

namespace vf {
namespace {

namespace fs = std::filesystem;

const fs::path kSource = VOXFALL_SOURCE_DIR;

// The texts between backticks on a line, in order.
std::vector<std::string> backticked(const std::string& line) {
  std::vector<std::string> out;
  std::size_t at = 0;
  while (true) {
    const std::size_t open = line.find('`', at);
    if (open == std::string::npos) break;
    const std::size_t close = line.find('`', open + 1);
    if (close == std::string::npos) break;
    out.push_back(line.substr(open + 1, close - open - 1));
    at = close + 1;
  }
  return out;
}

// "[simulation]" -> "simulation", "[[bodies]]" -> "bodies"; "" when not a table name.
std::string tablePath(const std::string& s) {
  if (s.size() >= 4 && s.rfind("[[", 0) == 0 && s.substr(s.size() - 2) == "]]")
    return s.substr(2, s.size() - 4);
  if (s.size() >= 2 && s.front() == '[' && s.back() == ']') return s.substr(1, s.size() - 2);
  return "";
}

// Every key the reference documents, as full dotted paths ("simulation.rest.speed").
std::set<std::string> documentedKeys(const std::string& markdown) {
  std::set<std::string> keys;
  std::vector<std::string> tables;
  std::istringstream in(markdown);
  std::string line;
  bool inFence = false;
  while (std::getline(in, line)) {
    if (line.rfind("```", 0) == 0) inFence = !inFence;
    if (inFence) continue;
    if (line.rfind('#', 0) == 0) {
      tables.clear();
      for (const std::string& s : backticked(line))
        if (const std::string p = tablePath(s); !p.empty()) tables.push_back(p);
    } else if (line.rfind("| `", 0) == 0 && !tables.empty()) {
      const std::string key = backticked(line).front();
      for (const std::string& t : tables) keys.insert(t + "." + key);
    }
  }
  return keys;
}

// Every key the loader accepts, as full dotted paths ("simulation" at the top level).
std::set<std::string> acceptedKeys(const std::vector<SceneTableKeys>& tables) {
  std::set<std::string> keys;
  for (const SceneTableKeys& t : tables)
    for (const std::string& k : t.keys) keys.insert(t.path.empty() ? k : t.path + "." + k);
  return keys;
}

// A documented key also documents the tables on its path ("shapes.NAME.mesh" documents
// "shapes" and "shapes.NAME").
std::set<std::string> withPrefixes(const std::set<std::string>& keys) {
  std::set<std::string> out = keys;
  for (const std::string& k : keys)
    for (std::size_t dot = k.find('.'); dot != std::string::npos; dot = k.find('.', dot + 1))
      out.insert(k.substr(0, dot));
  return out;
}

// One line per disagreement between the loader's keys and the reference's.
std::vector<std::string> keyProblems(const std::vector<SceneTableKeys>& tables,
                                     const std::string& markdown) {
  const std::set<std::string> accepted = acceptedKeys(tables);
  const std::set<std::string> documented = documentedKeys(markdown);
  const std::set<std::string> covered = withPrefixes(documented);
  std::vector<std::string> problems;
  for (const std::string& k : accepted)
    if (!covered.count(k)) problems.push_back("accepted but not documented: " + k);
  for (const std::string& k : documented)
    if (!accepted.count(k)) problems.push_back("documented but refused: " + k);
  return problems;
}

// The ```toml scene blocks of a markdown text, in order.
std::vector<std::string> sceneBlocks(const std::string& markdown) {
  std::vector<std::string> blocks;
  std::istringstream in(markdown);
  std::string line;
  std::string* current = nullptr;
  while (std::getline(in, line)) {
    if (current != nullptr) {
      if (line.rfind("```", 0) == 0)
        current = nullptr;
      else
        *current += line + "\n";
    } else if (line.rfind("```toml scene", 0) == 0) {
      blocks.emplace_back();
      current = &blocks.back();
    }
  }
  return blocks;
}

// Loads each scene block from a file in a folder that sees scenes/meshes and scenes/terrain as
// a file in scenes/ does; one line per block that does not load.
std::vector<std::string> sceneBlockProblems(const std::string& markdown) {
  const fs::path dir =
      fs::temp_directory_path() / ("voxfall_scene_reference_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  for (const char* sub : {"meshes", "terrain"})
    fs::create_directory_symlink(kSource / "scenes" / sub, dir / sub);
  std::vector<std::string> problems;
  const std::vector<std::string> blocks = sceneBlocks(markdown);
  for (std::size_t i = 0; i < blocks.size(); ++i) {
    const fs::path file = dir / ("block_" + std::to_string(i) + ".toml");
    std::ofstream(file) << blocks[i];
    try {
      loadScene(file.string());
    } catch (const InputError& e) {
      problems.push_back("scene block " + std::to_string(i + 1) + ": " + e.what());
    }
  }
  fs::remove_all(dir);
  return problems;
}

std::string joined(const std::vector<std::string>& lines) {
  std::string out;
  for (const std::string& l : lines) out += l + "\n";
  return out;
}

const std::string kReference = (kSource / "docs" / "scene-format.md").string();

TEST(SceneReference, DocumentsExactlyTheKeysTheLoaderAccepts) {
  ASSERT_TRUE(fs::exists(kReference));
  const std::vector<std::string> problems =
      keyProblems(sceneTableKeys(), test::readFile(kReference));
  EXPECT_TRUE(problems.empty()) << joined(problems);
}

TEST(SceneReference, EverySceneBlockLoads) {
  const std::string text = test::readFile(kReference);
  ASSERT_FALSE(sceneBlocks(text).empty()) << "the reference shows no complete scene";
  const std::vector<std::string> problems = sceneBlockProblems(text);
  EXPECT_TRUE(problems.empty()) << joined(problems);
}

// The oracles on a reference of two tables: one key left out, one key the loader refuses, an
// inline table's keys, a heading naming two tables, and a row outside any table heading.
TEST(SceneReference, KeyCheckReportsMissingAndExtraKeys) {
  const std::vector<SceneTableKeys> tables = {
      {"", {"output", "camera", "cameras"}}, {"output", {"width", "height", "crf"}},
      {"camera", {"fov", "path"}},           {"camera.path", {"time"}},
      {"cameras.NAME", {"fov", "path"}},     {"cameras.NAME.path", {"time"}},
  };
  const std::string complete =
      "# Scenes\n| `ignored` | row outside a table heading |\n"
      "## `[output]`\n| key | type |\n|---|---|\n| `width` | int |\n| `height` | int |\n"
      "| `crf` | int |\n```toml\n| `inside_a_fence` |\n```\n"
      "## `[camera]` and `[cameras.NAME]`\n| `fov` | number |\n| `path` | array |\n"
      "| `path.time` | number |\n";
  EXPECT_TRUE(keyProblems(tables, complete).empty()) << joined(keyProblems(tables, complete));

  std::string broken = complete;
  broken.replace(broken.find("| `crf` | int |\n"), 16, "| `gamma` | number |\n");
  const std::vector<std::string> problems = keyProblems(tables, broken);
  EXPECT_EQ(problems, (std::vector<std::string>{"accepted but not documented: output.crf",
                                                "documented but refused: output.gamma"}));

  std::string noPathKey = complete;
  noPathKey.erase(noPathKey.find("| `path.time` | number |\n"), 25);
  EXPECT_EQ(keyProblems(tables, noPathKey),
            (std::vector<std::string>{"accepted but not documented: camera.path.time",
                                      "accepted but not documented: cameras.NAME.path.time"}));
}

TEST(SceneReference, SceneBlockCheckReportsABlockThatDoesNotLoad) {
  const std::string good =
      "```toml scene\n[shapes.cube]\nmesh = \"meshes/cube.obj\"\ndensity = 800\n"
      "[[bodies]]\nshape = \"cube\"\nposition = [0, 0, 1]\n```\n";
  EXPECT_TRUE(sceneBlockProblems(good).empty()) << joined(sceneBlockProblems(good));
  // The reference's old mistake: a body of a shape the scene does not define.
  const std::string bad = good + "```toml\nnot = 'a scene block'\n```\n" +
                          "```toml scene\n[[bodies]]\nshape = \"block\"\n```\n";
  ASSERT_EQ(sceneBlocks(bad).size(), 2u);
  const std::vector<std::string> problems = sceneBlockProblems(bad);
  ASSERT_EQ(problems.size(), 1u) << joined(problems);
  EXPECT_NE(problems[0].find("scene block 2"), std::string::npos) << problems[0];
  EXPECT_NE(problems[0].find("'block'"), std::string::npos) << problems[0];
}

}  // namespace
}  // namespace vf

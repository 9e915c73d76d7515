// Which method a scene file runs (the `[simulation] method` key, scene_loader.cpp): without the
// key the fast path (contact reduction and sleeping), with `method = "paper"` the paper's
// method. Oracles: the golden suite's pinned checksum of example 1 (tests/golden/cubes, made by
// `voxfall regress` and the paper's method), and for the fast path what the run's counters can
// only show when the extensions ran: fewer contacts solved than leaf contacts found, and body
// steps spent asleep.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "sim/recorder.h"
#include "sim/scene/scene.h"
#include "tests/support/test_world.h"

namespace vf {
namespace {

namespace fs = std::filesystem;

std::string readFile(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

RunSummary runWhole(const SceneSpec& spec) {
  BuiltScene built = buildScene(spec);
  Recorder recorder(*built.world, spec.fps, spec.duration);
  for (int k = 0; k < recorder.frameCount(); ++k) recorder.advanceToFrame(k);
  return recorder.summary();
}

TEST(MethodKey, PaperKeyRunsThePapersMethodWithItsPinnedChecksum) {
  const SceneSpec spec = loadScene(test::sourcePath("scenes/cubes.toml"));
  EXPECT_FALSE(spec.contactReduction);
  EXPECT_FALSE(spec.sleep);
  std::string pinned = readFile(test::sourcePath("tests/golden/cubes/checksum.txt"));
  pinned.erase(pinned.find_last_not_of(" \n") + 1);
  const RunSummary run = runWhole(spec);
  EXPECT_EQ(run.checksumHex(), pinned);
  EXPECT_EQ(run.totals.contacts, run.totals.leafContacts) << "every leaf contact solved";
  EXPECT_EQ(run.totals.sleepingBodySteps, 0u);
}

TEST(MethodKey, WithoutTheKeyASceneRunsTheFastPath) {
  // Example 1 without its method line, next to a copy of its mesh, run 4 s: both cubes rest by
  // 2 s (example 1), so each sleeps by 2.5 s.
  const fs::path dir =
      fs::temp_directory_path() / ("voxfall_method_test_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir / "meshes");
  fs::copy_file(test::sourcePath("scenes/meshes/cube.obj"), dir / "meshes/cube.obj");
  std::istringstream shipped(readFile(test::sourcePath("scenes/cubes.toml")));
  std::ofstream out(dir / "cubes.toml");
  int dropped = 0;
  for (std::string line; std::getline(shipped, line);) {
    if (line.rfind("method", 0) == 0) {
      ++dropped;
      continue;
    }
    out << line << '\n';
  }
  out.close();
  ASSERT_EQ(dropped, 1) << "test bug: cubes.toml has one method line";
  SceneSpec spec = loadScene((dir / "cubes.toml").string());
  EXPECT_TRUE(spec.contactReduction);
  EXPECT_TRUE(spec.sleep);
  spec.duration = 4.0;
  const BuiltScene built = buildScene(spec);
  EXPECT_TRUE(built.world->def().contactReduction);
  EXPECT_TRUE(built.world->def().sleep);
  const RunSummary run = runWhole(spec);
  fs::remove_all(dir);
  EXPECT_LT(run.totals.contacts, run.totals.leafContacts) << "contacts were reduced";
  EXPECT_GT(run.totals.sleepingBodySteps, 0u) << "the cubes fell asleep";
}

}  // namespace
}  // namespace vf

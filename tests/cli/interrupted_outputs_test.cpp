// Interrupted means said, and no litter, with real child processes: an interrupted `simulate
// --summary` writes a summary that says it was interrupted and at which frame; the stop policy
// (render/run/stop_policy.h) of the polling commands that output_rules_test and
// ensemble_command_test do not stop: `export` stopped while it simulates writes nothing and exits
// 130 / 143, and `ensemble` stopped by SIGTERM keeps its complete realisations and exits 143 (the
// commands that do not poll are stopped in stop_every_command_test); the temporary files of a
// run killed with SIGKILL are removed by the next run that writes into the same folder (only
// those whose process is gone); and on a full disk (a small tmpfs, where this machine lets the
// test mount one) a run fails with one clear error and leaves nothing but complete files.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/mount.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <nlohmann/json.hpp>
#include <regex>
#include <string>
#include <thread>
#include <vector>

#include "tests/support/chute_dem.h"
#include "tests/support/voxfall_command.h"

namespace {

namespace fs = std::filesystem;
using vf::test::readFile;
using vf::test::runVoxfall;

const std::string kExe = VOXFALL_EXE;

// The temporary output files (".NAME.partial-PID-N.EXT") in `folder`.
std::vector<std::string> partials(const fs::path& folder) {
  std::vector<std::string> out;
  for (const auto& e : fs::directory_iterator(folder))
    if (e.path().filename().string().find(".partial-") != std::string::npos)
      out.push_back(e.path().filename().string());
  return out;
}

class InterruptedOutputs : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = vf::test::scratchFolder("voxfall_interrupted", info->name());
    vf::test::copyCubesScene(fs::path(VOXFALL_SOURCE_DIR) / "scenes", dir_, {{"long.toml", 600}});
  }
  void TearDown() override {
    if (mounted_) ::umount2((dir_ / "disk").c_str(), MNT_DETACH);
    fs::remove_all(dir_);
  }

  // Starts `voxfall ARGS...` in dir_ and sends `sig` once `ready()` holds; returns the child's
  // wait status.
  int interrupt(const std::vector<std::string>& args, int sig, const std::function<bool()>& ready) {
    return vf::test::interruptVoxfall(kExe, dir_, args, sig, ready);
  }

  fs::path dir_;
  bool mounted_ = false;
};

TEST_F(InterruptedOutputs, AnInterruptedSimulateSummarySaysSo) {
  ASSERT_EQ(runVoxfall(kExe, dir_, "simulate cubes.toml --summary whole.json -q").code, 0);
  EXPECT_TRUE(nlohmann::json::parse(readFile(dir_ / "whole.json")).at("interrupted").is_null());
  fs::create_directories(dir_ / "cut");
  const int status = interrupt(
      {"simulate", "long.toml", "--csv", "cut/run.csv", "--summary", "cut/run.json", "-q"}, SIGINT,
      [&] {  // CSV rows on disk: frames are flowing (the summary's file stays empty)
        std::uintmax_t bytes = 0;
        std::error_code ec;
        for (const std::string& p : partials(dir_ / "cut"))
          bytes += fs::file_size(dir_ / "cut" / p, ec);
        return bytes > 0 && !ec;
      });
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 130);
  const auto json = nlohmann::json::parse(readFile(dir_ / "cut" / "run.json"));
  const auto& cut = json.at("interrupted");
  ASSERT_TRUE(cut.is_object()) << json.dump();
  EXPECT_EQ(cut.at("signal"), "SIGINT");
  const int frames = json.at("frames").get<int>();
  EXPECT_EQ(cut.at("frames").get<int>(), frames);
  EXPECT_GT(frames, 0);
  EXPECT_LT(frames, 18001);
  // The time of the last frame written (30 fps).
  EXPECT_DOUBLE_EQ(cut.at("time").get<double>(), (frames - 1) / 30.0);
}

// The signal goes once the first progress line is on stderr: the simulation is under way
// (progress starts after a quiet second, long after the stop handlers are in place).
TEST_F(InterruptedOutputs, AnExportStoppedWhileSimulatingWritesNothing) {
  fs::create_directories(dir_ / "out");
  for (const int sig : {SIGINT, SIGTERM}) {
    fs::remove(dir_ / "stderr.txt");
    const int status = vf::test::interruptVoxfall(
        kExe, dir_, {"export", "long.toml", "-o", "out/long.glb"}, sig,
        [&] { return !readFile(dir_ / "stderr.txt").empty(); }, "stderr.txt");
    ASSERT_TRUE(WIFEXITED(status)) << "signal " << sig;
    EXPECT_EQ(WEXITSTATUS(status), 128 + sig);
    const std::string err = readFile(dir_ / "stderr.txt");
    EXPECT_NE(err.find("voxfall: interrupted; nothing written\n"), std::string::npos) << err;
    EXPECT_TRUE(fs::is_empty(dir_ / "out")) << "neither the .glb nor a temporary file";
  }
}

TEST_F(InterruptedOutputs, AnEnsembleStoppedBySigtermKeepsItsCompleteRealisations) {
  ASSERT_TRUE(vf::test::writeChuteDem(dir_ / "chute.tif"));
  vf::test::writeChuteScene(dir_, vf::test::kChuteEnsemble, 10.0);
  const std::regex done("ensemble: ([0-9]+)/");
  const int status = vf::test::interruptVoxfall(
      kExe, dir_, {"ensemble", "scene.toml", "--runs", "100000", "--jobs", "2", "-o", "int"},
      SIGTERM,
      [&] {  // a progress line that counts a complete realisation
        const std::string err = readFile(dir_ / "stderr.txt");
        std::smatch m;
        return std::regex_search(err, m, done) && std::stoll(m[1]) > 0;
      },
      "stderr.txt");
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 143);
  const std::string err = readFile(dir_ / "stderr.txt");
  EXPECT_NE(err.find("voxfall: interrupted; the files hold the "), std::string::npos) << err;
  std::size_t rows = 0;
  const std::string runs = readFile(dir_ / "int" / "runs.csv");
  for (const char c : runs) rows += c == '\n';
  ASSERT_GE(rows, 2u) << "a header and at least one realisation";
  const auto json = nlohmann::json::parse(readFile(dir_ / "int" / "summary.json"));
  EXPECT_EQ(json.at("interrupted").at("signal"), "SIGTERM") << json.dump();
  EXPECT_EQ(json.at("interrupted").at("runs").get<std::size_t>(), rows - 1) << json.dump();
  EXPECT_TRUE(partials(dir_ / "int").empty());
}

TEST_F(InterruptedOutputs, AKilledRunsTemporaryFilesAreGoneAfterTheNextRun) {
  fs::create_directories(dir_ / "out");
  const int status = interrupt({"simulate", "long.toml", "--csv", "out/run.csv", "-q"}, SIGKILL,
                               [&] { return !partials(dir_ / "out").empty(); });
  ASSERT_TRUE(WIFSIGNALED(status));
  ASSERT_EQ(partials(dir_ / "out").size(), 1u) << "SIGKILL leaves the temporary file";
  // Two more: one of a process that does not exist (above any pid_max), one of a process that
  // runs (this test), which must be kept.
  std::ofstream(dir_ / "out" / ".gone.partial-999999999-0.csv") << "x";
  const std::string mine = ".mine.partial-" + std::to_string(::getpid()) + "-0.csv";
  std::ofstream(dir_ / "out" / mine) << "x";
  ASSERT_EQ(runVoxfall(kExe, dir_, "simulate cubes.toml --csv out/next.csv -q").code, 0);
  EXPECT_EQ(partials(dir_ / "out"), std::vector<std::string>{mine});
  EXPECT_FALSE(fs::exists(dir_ / "out" / "run.csv"));
}

TEST_F(InterruptedOutputs, AFullDiskIsOneClearErrorAndLeavesOnlyCompleteFiles) {
  ASSERT_TRUE(vf::test::writeChuteDem(dir_ / "chute.tif"));
  vf::test::writeChuteScene(dir_, vf::test::kChuteEnsemble);
  const std::string args = "ensemble scene.toml --runs 6 --converge -q -o ";
  ASSERT_EQ(runVoxfall(kExe, dir_, args + "ref").code, 0);
  fs::create_directories(dir_ / "disk");
  // 64 KiB: room for the journal and a few rasters, not for all of the outputs.
  if (::mount("tmpfs", (dir_ / "disk").c_str(), "tmpfs", 0, "size=64k") != 0)
    GTEST_SKIP() << "cannot mount a tmpfs here (" << std::strerror(errno)
                 << "); the full-disk case is not tested";
  mounted_ = true;
  const auto full = runVoxfall(kExe, dir_, args + "disk/e");
  EXPECT_EQ(full.code, 1) << full.err;
  // The output is named (not its temporary name), with the system's or GDAL's reason.
  EXPECT_EQ(full.err.find(".partial-"), std::string::npos) << full.err;
  EXPECT_TRUE(full.err.find("No space left on device") != std::string::npos ||
              full.err.find("disk full") != std::string::npos)
      << full.err;
  EXPECT_EQ(full.err.rfind("voxfall: error: ", 0), 0u) << full.err;
  EXPECT_EQ(std::count(full.err.begin(), full.err.end(), '\n'), 1) << full.err;
  EXPECT_TRUE(partials(dir_ / "disk" / "e").empty());
  // Every output left is complete: the same bytes as the reference run's.
  for (const auto& e : fs::directory_iterator(dir_ / "disk" / "e")) {
    const std::string name = e.path().filename().string();
    if (name == "ensemble.journal") continue;
    EXPECT_TRUE(readFile(e.path()) == readFile(dir_ / "ref" / name)) << name << " is not whole";
  }
}

}  // namespace

// Long ensembles lose no work (docs/ensembles.md, "Long runs"), with real processes on the
// small synthetic chute (tests/support/chute_dem.h). The oracle is always one uninterrupted run
// of the same ensemble: a run killed with SIGKILL and resumed, a run extended from 20 to 40
// realisations, and two shards merged must each write the same bytes, file for file (the
// journal aside: its records are in the order realisations finished). A resume with a changed
// scene or option is refused naming the difference, and shards that overlap, miss realisations
// or belong to another ensemble are refused by the merge, as is a journal of an older format.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <string>
#include <thread>

#include "tests/support/chute_dem.h"
#include "tests/support/voxfall_command.h"

namespace {

namespace fs = std::filesystem;
using vf::test::readFile;
using vf::test::runVoxfall;

const std::string kExe = VOXFALL_EXE;
const std::string kJournal = "ensemble.journal";

class EnsembleJournalTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = vf::test::scratchFolder("voxfall_journal_test", info->name());
    ASSERT_TRUE(vf::test::writeChuteDem(dir_ / "chute.tif"));
    vf::test::writeChuteScene(dir_, vf::test::kChuteEnsemble);
  }
  void TearDown() override { fs::remove_all(dir_); }

  // `voxfall ensemble scene.toml ARGS -q`, which must succeed.
  vf::test::CommandResult ensemble(const std::string& args) {
    const auto r = runVoxfall(kExe, dir_, "ensemble scene.toml -q --seed 7 " + args);
    EXPECT_EQ(r.code, 0) << args << "\n" << r.err;
    return r;
  }

  // Every file of folder `b` is the same bytes as in folder `a`, and the other way round (the
  // journal aside); no temporary file is left in `b`.
  void expectSameOutputs(const std::string& a, const std::string& b) const {
    std::map<std::string, std::string> first, second;
    for (const auto& e : fs::directory_iterator(dir_ / a))
      if (e.path().filename() != kJournal) first[e.path().filename()] = readFile(e.path());
    for (const auto& e : fs::directory_iterator(dir_ / b))
      if (e.path().filename() != kJournal) second[e.path().filename()] = readFile(e.path());
    EXPECT_GE(first.size(), 9u * 3 + 2) << a;
    for (const auto& [name, bytes] : first) {
      ASSERT_TRUE(second.count(name)) << b << " lacks " << name;
      EXPECT_TRUE(bytes == second.at(name)) << name << " differs between " << a << " and " << b;
    }
    for (const auto& [name, bytes] : second) EXPECT_TRUE(first.count(name)) << b << ": " << name;
  }

  fs::path dir_;
};

// The realisations a run took from the journal, as its last stderr line says ("..., K taken
// from the journal"); 0 when it says none.
int takenFromJournal(const std::string& err) {
  std::smatch m;
  return std::regex_search(err, m, std::regex("(\\d+) taken from the journal")) ? std::stoi(m[1])
                                                                                : 0;
}

TEST_F(EnsembleJournalTest, AKilledRunResumedWritesTheBytesOfOneRun) {
  ensemble("--runs 40 --jobs 2 --converge -o ref");
  const pid_t child = vf::test::startVoxfall(kExe, dir_,
                                             {"ensemble", "scene.toml", "--runs", "40", "--seed",
                                              "7", "--jobs", "2", "--converge", "-q", "-o", "cut"});
  // Killed as soon as the journal holds a realisation (a few hundred bytes past its header and
  // the --runs record), long before the 40 are done.
  const fs::path journal = dir_ / "cut" / kJournal;
  std::uintmax_t started = 0;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  while (std::chrono::steady_clock::now() < deadline) {
    std::error_code ec;
    const std::uintmax_t size = fs::file_size(journal, ec);
    if (!ec && started == 0) started = size;
    if (!ec && size > started + 100) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  ::kill(child, SIGKILL);
  int status = 0;
  ::waitpid(child, &status, 0);
  ASSERT_TRUE(WIFSIGNALED(status)) << "the run ended before it was killed";
  EXPECT_FALSE(fs::exists(dir_ / "cut" / "runs.csv"));

  const auto resumed = ensemble("--runs 40 --jobs 2 --converge --resume -o cut");
  const int taken = takenFromJournal(resumed.err);
  EXPECT_GT(taken, 0) << resumed.err;
  EXPECT_LT(taken, 40) << resumed.err;
  expectSameOutputs("ref", "cut");  // temporary files of the killed run included: none left
}

TEST_F(EnsembleJournalTest, ExtendingTwentyToFortyEqualsAFortyRun) {
  ensemble("--runs 40 --jobs 2 -o ref");
  ensemble("--runs 20 --jobs 2 -o ext");
  const auto more = ensemble("--runs 40 --jobs 2 --resume -o ext");
  EXPECT_EQ(takenFromJournal(more.err), 20) << more.err;
  EXPECT_NE(more.err.find("20 realisations run"), std::string::npos) << more.err;
  expectSameOutputs("ref", "ext");
  // A resume of a complete journal runs nothing and writes the same files again.
  const auto again = ensemble("--runs 40 --resume -o ext");
  EXPECT_EQ(takenFromJournal(again.err), 40) << again.err;
  expectSameOutputs("ref", "ext");
}

TEST_F(EnsembleJournalTest, ARecordCutShortIsDroppedOnResume) {
  ensemble("--runs 6 -o ref");
  ensemble("--runs 6 -o torn");
  // A kill in the middle of a write: half a record's head at the end of the journal.
  const std::string head("VFJR\x01\0\0", 7);
  std::ofstream(dir_ / "torn" / kJournal, std::ios::app | std::ios::binary)
      .write(head.data(), static_cast<std::streamsize>(head.size()));
  const auto resumed = ensemble("--runs 6 --resume -o torn");
  EXPECT_NE(resumed.err.find("dropped a record cut short (7 bytes)"), std::string::npos)
      << resumed.err;
  expectSameOutputs("ref", "torn");
}

TEST_F(EnsembleJournalTest, TwoShardsMergedEqualOneRun) {
  ensemble("--runs 12 --jobs 2 --converge -o ref");
  ensemble("--runs 12 --shard 0/2 -o s0");
  ensemble("--runs 12 --shard 1/2 --jobs 2 -o s1");
  EXPECT_FALSE(fs::exists(dir_ / "s0" / "runs.csv")) << "a shard writes its journal only";
  const auto merged = runVoxfall(kExe, dir_, "ensemble-merge s0 s1 --converge -q -o merged");
  ASSERT_EQ(merged.code, 0) << merged.err;
  expectSameOutputs("ref", "merged");
  // The merged journal continues like any other: extended to 14.
  ensemble("--runs 14 --converge -o ref14");
  ensemble("--runs 14 --converge --resume -o merged");
  expectSameOutputs("ref14", "merged");
}

TEST_F(EnsembleJournalTest, ShardsThatOverlapMissOrDifferAreRefusedByTheMerge) {
  ensemble("--runs 12 --shard 0/2 -o s0");
  const auto missing = runVoxfall(kExe, dir_, "ensemble-merge s0 -q -o m");
  EXPECT_EQ(missing.code, 1);
  EXPECT_NE(missing.err.find("realisations 1, 3, 5, 7, 9, ... (6 in all) of --runs 12 are in "
                             "none of the journals"),
            std::string::npos)
      << missing.err;
  const auto overlap = runVoxfall(kExe, dir_, "ensemble-merge s0 s0/ensemble.journal -q -o m");
  EXPECT_EQ(overlap.code, 1);
  EXPECT_NE(overlap.err.find("holds realisation 0, which s0 holds too: the shards overlap"),
            std::string::npos)
      << overlap.err;
  const auto other =
      runVoxfall(kExe, dir_, "ensemble scene.toml -q --seed 8 --runs 12 --shard 1/2 -o s1");
  ASSERT_EQ(other.code, 0) << other.err;
  const auto mismatch = runVoxfall(kExe, dir_, "ensemble-merge s0 s1 -q -o m");
  EXPECT_EQ(mismatch.code, 1);
  EXPECT_NE(mismatch.err.find("s1: is not a shard of the same ensemble as s0: --seed: the "
                              "journal's run has 7, this run 8"),
            std::string::npos)
      << mismatch.err;
  EXPECT_FALSE(fs::exists(dir_ / "m" / "runs.csv"));
  // A shard given as a number out of range is a usage error.
  EXPECT_EQ(runVoxfall(kExe, dir_, "ensemble scene.toml --runs 4 --shard 2/2 -o x").code, 2);
}

TEST_F(EnsembleJournalTest, AResumeWithAChangedSceneOrOptionIsRefusedNamingIt) {
  ensemble("--runs 4 -o a");
  const std::string before = readFile(dir_ / "a" / "runs.csv");
  const std::pair<std::string, std::string> cases[] = {
      {"--seed 8", "cannot resume: --seed: the journal's run has 7, this run 8"},
      {"--seed 7 --level 3",
       "cannot resume: --level: the journal's run has none (the scene's), this run 3"},
      {"--seed 7 --paths", "cannot resume: --paths: the journal's run has off, this run on"},
  };
  for (const auto& [option, message] : cases) {
    const auto r =
        runVoxfall(kExe, dir_, "ensemble scene.toml -q --runs 4 --resume -o a " + option);
    EXPECT_EQ(r.code, 1) << option;
    EXPECT_NE(r.err.find(message), std::string::npos) << r.err;
  }
  // The scene's ground changed: its file is named.
  std::string bouncier = vf::test::kChuteEnsemble;
  bouncier.replace(bouncier.find("[0.3, 0.4]"), 10, "[0.6, 0.7]");
  vf::test::writeChuteScene(dir_, bouncier);
  const auto changed =
      runVoxfall(kExe, dir_, "ensemble scene.toml -q --seed 7 --runs 4 --resume -o a");
  EXPECT_EQ(changed.code, 1);
  EXPECT_NE(changed.err.find("cannot resume: scene.toml has changed since the journal was written"),
            std::string::npos)
      << changed.err;
  EXPECT_EQ(readFile(dir_ / "a" / "runs.csv"), before) << "a refused resume wrote nothing";
  // A new run into the folder is refused too, pointing at --resume.
  const auto fresh = runVoxfall(kExe, dir_, "ensemble scene.toml -q --seed 7 --runs 4 -o a");
  EXPECT_EQ(fresh.code, 1);
  EXPECT_NE(fresh.err.find("continue it with --resume"), std::string::npos) << fresh.err;
  // And --resume with no journal says there is none.
  const auto none = runVoxfall(kExe, dir_, "ensemble scene.toml -q --runs 4 --resume -o b");
  EXPECT_EQ(none.code, 1);
  EXPECT_NE(none.err.find("no journal to resume"), std::string::npos) << none.err;
}

// A journal of the previous format (its records lack the tree impacts) is one error naming the
// file, for a resume and for a merge, and nothing is written.
TEST_F(EnsembleJournalTest, AJournalOfAnOlderFormatIsRefusedByResumeAndMerge) {
  ensemble("--runs 4 -o a");
  const std::string before = readFile(dir_ / "a" / "runs.csv");
  std::string bytes = readFile(dir_ / "a" / kJournal);
  const std::size_t at = bytes.find("\"version\":3");
  ASSERT_NE(at, std::string::npos) << bytes.substr(0, 200);
  bytes.replace(at, 11, "\"version\":2");
  std::ofstream(dir_ / "a" / kJournal, std::ios::binary) << bytes;
  const std::string message =
      "ensemble.journal: journal version 2 was written by an older voxfall (this one reads "
      "version 3); it cannot be resumed or merged: run the ensemble again";
  for (const std::string command :
       {"ensemble scene.toml -q --seed 7 --runs 6 --resume -o a", "ensemble-merge a -q -o m"}) {
    const auto r = runVoxfall(kExe, dir_, command);
    EXPECT_EQ(r.code, 1) << command;
    EXPECT_NE(r.err.find(message), std::string::npos) << command << "\n" << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  }
  EXPECT_EQ(readFile(dir_ / "a" / "runs.csv"), before);
  EXPECT_FALSE(fs::exists(dir_ / "m"));
}

}  // namespace

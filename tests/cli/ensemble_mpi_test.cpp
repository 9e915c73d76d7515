// `mpirun -np 2 voxfall ensemble` writes the same bytes as one process (the realisations are
// split round robin over the ranks and reduced on rank 0 in index order), and an MPI run with
// one rank killed (SIGKILL), finished by a resume without MPI, writes them too: rank 0
// journals every realisation as it arrives.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <string>
#include <thread>

#include "tests/support/chute_dem.h"
#include "tests/support/voxfall_command.h"

namespace {

namespace fs = std::filesystem;

// A scratch folder with the chute and its scene.
fs::path chuteFolder(const std::string& name) {
  const fs::path dir = vf::test::scratchFolder("voxfall_ensemble_mpi_test", name);
  EXPECT_TRUE(vf::test::writeChuteDem(dir / "chute.tif"));
  vf::test::writeChuteScene(dir, vf::test::kChuteEnsemble);
  return dir;
}

TEST(EnsembleMpiTest, TwoRanksWriteTheSameBytesAsOneProcess) {
  const fs::path dir = chuteFolder("two_ranks");
  const std::string args = "ensemble scene.toml --runs 7 --seed 3 --converge --paths -q";
  const auto one = vf::test::runVoxfall(VOXFALL_EXE, dir, args + " -o one");
  ASSERT_EQ(one.code, 0) << one.err;
  // OpenMPI refuses root without both the flag and these variables.
  ::setenv("OMPI_ALLOW_RUN_AS_ROOT", "1", 1);
  ::setenv("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1", 1);
  const std::string launcher =
      std::string(VOXFALL_MPIEXEC) + "' --allow-run-as-root --oversubscribe -np 2 '" + VOXFALL_EXE;
  const auto two = vf::test::runVoxfall(launcher, dir, args + " -o two");
  ASSERT_EQ(two.code, 0) << two.out << two.err;
  // Rank 0 reports both ranks (the run did split).
  EXPECT_NE(two.err.find("x 2 ranks"), std::string::npos) << two.err;
  std::size_t compared = 0;
  for (const auto& e : fs::directory_iterator(dir / "one")) {
    // The journal's records are in the order realisations finished: not compared.
    if (e.path().filename() == "ensemble.journal") continue;
    const fs::path other = dir / "two" / e.path().filename();
    ASSERT_TRUE(fs::exists(other)) << other;
    EXPECT_TRUE(vf::test::readFile(e.path()) == vf::test::readFile(other))
        << e.path().filename() << " differs between 1 process and 2 MPI ranks";
    ++compared;
  }
  EXPECT_EQ(compared, 9u * 3 + 4);
  fs::remove_all(dir);
}

// The process id of the voxfall rank `rank` started with VOXFALL_TEST_MARK=`mark`, or 0.
pid_t rankPid(const std::string& mark, int rank) {
  for (const auto& e : fs::directory_iterator("/proc")) {
    const std::string env = vf::test::readFile(e.path() / "environ");
    const auto has = [&](const std::string& v) {
      return env.find(std::string(1, '\0') + v + '\0') != std::string::npos ||
             env.rfind(v + '\0', 0) == 0;
    };
    const std::string exe = vf::test::readFile(e.path() / "cmdline");
    if (has("VOXFALL_TEST_MARK=" + mark) && has("OMPI_COMM_WORLD_RANK=" + std::to_string(rank)) &&
        exe.find("voxfall") != std::string::npos && exe.find("mpirun") == std::string::npos)
      return static_cast<pid_t>(std::stol(e.path().filename().string()));
  }
  return 0;
}

// Whether process `pid` still runs (a zombie has exited).
bool running(pid_t pid) {
  const std::string stat = vf::test::readFile("/proc/" + std::to_string(pid) + "/stat");
  const std::size_t close = stat.rfind(')');
  return close != std::string::npos && close + 2 < stat.size() && stat[close + 2] != 'Z';
}

TEST(EnsembleMpiTest, ARunWithAKilledRankIsFinishedByAResumeWithoutMpi) {
  const fs::path dir = chuteFolder("killed_rank");
  const std::string args = "ensemble scene.toml --runs 40 --seed 3 --converge -q";
  const auto one = vf::test::runVoxfall(VOXFALL_EXE, dir, args + " -o one");
  ASSERT_EQ(one.code, 0) << one.err;
  const std::string mark = std::to_string(::getpid());
  ::setenv("VOXFALL_TEST_MARK", mark.c_str(), 1);
  ::setenv("OMPI_ALLOW_RUN_AS_ROOT", "1", 1);
  ::setenv("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1", 1);
  const pid_t mpirun = ::fork();
  if (mpirun == 0) {
    const std::string cmd = "cd '" + dir.string() + "' && exec '" + VOXFALL_MPIEXEC +
                            "' --allow-run-as-root --oversubscribe -np 2 '" + VOXFALL_EXE + "' " +
                            args + " -o two >/dev/null 2>&1";
    ::execl("/bin/sh", "sh", "-c", cmd.c_str(), static_cast<char*>(nullptr));
    ::_exit(127);
  }
  // Rank 1 is killed once rank 0's journal holds a realisation, long before the 40 are done.
  const fs::path journal = dir / "two" / "ensemble.journal";
  std::uintmax_t started = 0;
  pid_t rank1 = 0;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  while (std::chrono::steady_clock::now() < deadline) {
    std::error_code ec;
    const std::uintmax_t size = fs::file_size(journal, ec);
    if (!ec && started == 0) started = size;
    if (!ec && size > started + 100 && (rank1 = rankPid(mark, 1)) != 0) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  ASSERT_NE(rank1, 0) << "rank 1 not found";
  const pid_t rank0 = rankPid(mark, 0);
  ::kill(rank1, SIGKILL);
  int status = 0;
  ::waitpid(mpirun, &status, 0);  // mpirun ends the job when a rank dies
  // Rank 0 may outlive mpirun by a moment; its temporary files are removed by the resume only
  // once it is gone.
  while (rank0 != 0 && running(rank0) && std::chrono::steady_clock::now() < deadline)
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  EXPECT_FALSE(WIFEXITED(status) && WEXITSTATUS(status) == 0);
  EXPECT_FALSE(fs::exists(dir / "two" / "runs.csv"));
  ::unsetenv("VOXFALL_TEST_MARK");

  const auto resumed = vf::test::runVoxfall(VOXFALL_EXE, dir, args + " --resume -o two");
  ASSERT_EQ(resumed.code, 0) << resumed.err;
  EXPECT_NE(resumed.err.find("taken from the journal"), std::string::npos) << resumed.err;
  std::size_t compared = 0;
  for (const auto& e : fs::directory_iterator(dir / "one")) {
    if (e.path().filename() == "ensemble.journal") continue;
    EXPECT_TRUE(vf::test::readFile(e.path()) ==
                vf::test::readFile(dir / "two" / e.path().filename()))
        << e.path().filename() << " differs after the resume";
    ++compared;
  }
  EXPECT_EQ(compared, 9u * 3 + 3);
  std::size_t files = 0;
  for (const auto& e : fs::directory_iterator(dir / "two")) files += e.is_regular_file();
  EXPECT_EQ(files, compared + 1) << "only the outputs and the journal: no temporary files";
  fs::remove_all(dir);
}

}  // namespace

// `mpirun -np 2 voxfall ensemble` writes the same bytes as one process (the realisations are
// split round robin over the ranks and reduced on rank 0 in index order).
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <map>
#include <string>

#include "tests/support/chute_dem.h"
#include "tests/support/voxfall_command.h"

namespace {

namespace fs = std::filesystem;

TEST(EnsembleMpiTest, TwoRanksWriteTheSameBytesAsOneProcess) {
  const fs::path dir =
      fs::temp_directory_path() / ("voxfall_ensemble_mpi_test_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  ASSERT_TRUE(vf::test::writeChuteDem(dir / "chute.tif"));
  vf::test::writeChuteScene(dir, vf::test::kChuteEnsemble);
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
    const fs::path other = dir / "two" / e.path().filename();
    ASSERT_TRUE(fs::exists(other)) << other;
    EXPECT_TRUE(vf::test::readFile(e.path()) == vf::test::readFile(other))
        << e.path().filename() << " differs between 1 process and 2 MPI ranks";
    ++compared;
  }
  EXPECT_EQ(compared, 9u * 3 + 4);
  fs::remove_all(dir);
}

}  // namespace

// `voxfall simulate --csv` between steps: a box at rest on a 30-degree slope (1/60 s steps,
// 100 fps, so most rows fall inside a step) has zero velocity and a constant position in every
// row after it rests. The slope is the floor with gravity tilted 30 degrees from its normal,
// the same mechanics as a tilted floor under upright gravity. The step states come from the
// run's bake (every step's state), read back, so the rows are checked against the steps.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include "sim/bake.h"
#include "tests/support/voxfall_command.h"

namespace vf {
namespace {

TEST(CsvFrames, ABoxAtRestOnASlopeHasZeroVelocityAndAConstantPositionInEveryRow) {
  const auto dir = test::scratchFolder("voxfall_csv_frames", "slope");
  const double theta = 30.0 * std::numbers::pi / 180.0;
  {
    std::ofstream f(dir / "slope.toml");
    f.precision(17);
    f << "[simulation]\nduration = 2.0\nlevel = 3\nstep = \"1/60\"\nmethod = \"paper\"\nfps = 100\n"
      << "gravity = [" << 9.81 * std::sin(theta) << ", 0.0, " << -9.81 * std::cos(theta) << "]\n"
      << "[contact]\nfriction = { body_body = 0.3, body_ground = 0.8 }\n"  // 0.8 > tan 30
      << "[ground]\nplane = 0.0\n"
      << "[shapes.cube]\nmesh = \"" << VOXFALL_SOURCE_DIR
      << "/scenes/meshes/cube.obj\"\nscale = 0.2\ndensity = 800\n"
      << "[[bodies]]\nshape = \"cube\"\nposition = [0.0, 0.0, 0.0]\ndrop_height = 0.001\n";
  }
  const test::CommandResult r =
      test::runVoxfall(VOXFALL_EXE, dir, "simulate slope.toml -q --csv rows.csv --bake run.bake");
  ASSERT_EQ(r.code, 0) << r.err;
  const Bake bake = readBake((dir / "run.bake").string());
  std::ifstream csv(dir / "rows.csv");
  std::string line;
  std::getline(csv, line);  // header
  struct Row {
    double t;
    Vec3 x, v;
  };
  std::vector<Row> rows;
  while (std::getline(csv, line)) {
    std::stringstream s(line);
    std::vector<double> f;
    for (std::string cell; std::getline(s, cell, ',');) f.push_back(std::stod(cell));
    ASSERT_EQ(f.size(), 16u) << line;
    rows.push_back(Row{f[1], Vec3(f[3], f[4], f[5]), Vec3(f[10], f[11], f[12])});
  }
  std::filesystem::remove_all(dir);
  ASSERT_EQ(rows.size(), 201u);

  // Rest from the steps: from the first step after which every step's speed is below 1 mm/s.
  const double invMass = bake.bodies[0].invMass;
  std::size_t rest = bake.records.size();
  while (rest > 0 && (invMass * bake.records[rest - 1].states[0].P).norm() < 1e-3) --rest;
  ASSERT_LT(rest + 30, bake.records.size()) << "the box does not rest for half a second";
  const Vec3 xRest = bake.records[rest].states[0].x;
  double stepSpeed = 0, stepDrift = 0;
  for (std::size_t i = rest; i < bake.records.size(); ++i) {
    stepSpeed = std::max(stepSpeed, (invMass * bake.records[i].states[0].P).norm());
    stepDrift = std::max(stepDrift, (bake.records[i].states[0].x - xRest).norm());
  }
  // A row is a convex combination of its two bracketing steps: no faster, no further than
  // they are, to the rounding of that combination. The old rows moved the last step by
  // gravity's free motion: v off by up to g dt = 0.16 m/s, x by up to g dt^2 = 2.7 mm.
  int checked = 0;
  for (const Row& row : rows) {
    if (row.t < bake.records[rest].time) continue;
    EXPECT_LE(row.v.norm(), stepSpeed + 1e-12) << "t = " << row.t;
    EXPECT_LE((row.x - xRest).norm(), stepDrift + 1e-12) << "t = " << row.t;
    ++checked;
  }
  EXPECT_GT(checked, 50);
  EXPECT_LT(stepSpeed, 1e-3);
}

}  // namespace
}  // namespace vf

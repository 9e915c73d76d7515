// sim/ensemble: the cell walk against brute force, the percentile estimator and the per-cell
// statistics against hand computations, seeds, release draws, and threads that do not change
// a realisation.
#include "sim/ensemble/ensemble.h"

#include <gdal.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <set>
#include <string>
#include <vector>

#include "sim/core/error.h"
#include "sim/core/prng.h"
#include "sim/ensemble/ensemble_bake.h"
#include "sim/ensemble/ensemble_stats.h"
#include "sim/recorder.h"
#include "sim/scene/scene.h"
#include "tests/support/chute_dem.h"
#include "tests/support/segment_square.h"
#include "tests/support/test_world.h"

namespace vf {
namespace {

namespace fs = std::filesystem;

// Brute force: every cell whose closed square the segment meets (random segments pass exactly
// through a cell border or corner with probability zero, so closed and half-open squares agree).
std::set<std::int32_t> cellsByClipping(const Heightfield& g, const Vec3& a, const Vec3& b) {
  std::set<std::int32_t> out;
  for (int j = 0; j < g.ny; ++j)
    for (int i = 0; i < g.nx; ++i) {
      const double x = g.x0 + i * g.cell, y = g.y0 + j * g.cell, h = 0.5 * g.cell;
      if (test::segmentMeetsSquare(a.x(), a.y(), b.x(), b.y(), x - h, x + h, y - h, y + h))
        out.insert(j * g.nx + i);
    }
  return out;
}

TEST(EnsembleCells, SegmentWalkMeetsTheCellsBruteForceFinds) {
  const Heightfield g = test::flatHeightfield(7, 5, 2.0, 0.0, 10.0, 20.0);
  Prng rng(42);
  for (int t = 0; t < 200; ++t) {
    // Ends anywhere around the grid (some off it), and some short segments inside one cell.
    const Vec3 a(rng.uniform(5, 27), rng.uniform(15, 32), 0);
    const Vec3 b = t % 4 == 0 ? a + Vec3(rng.uniform(-0.3, 0.3), rng.uniform(-0.3, 0.3), 0)
                              : Vec3(rng.uniform(5, 27), rng.uniform(15, 32), 0);
    std::vector<std::int32_t> walk;
    cellsOnSegment(g, a, b, walk);
    const std::set<std::int32_t> unique(walk.begin(), walk.end());
    EXPECT_EQ(unique.size(), walk.size()) << "a cell met twice";
    EXPECT_EQ(unique, cellsByClipping(g, a, b)) << "segment " << t;
  }
  // A point: its own cell. Sample (3, 2) is at (16, 24); its cell spans x 15..17, y 23..25.
  std::vector<std::int32_t> one;
  cellsOnSegment(g, Vec3(16.9, 23.1, 0), Vec3(16.9, 23.1, 0), one);
  ASSERT_EQ(one.size(), 1u);
  EXPECT_EQ(one[0], 2 * 7 + 3);
}

TEST(EnsembleStats, NearestRankPercentileByHand) {
  std::vector<double> v(20);
  for (int k = 0; k < 20; ++k) v[static_cast<std::size_t>(k)] = k + 1;  // 1 .. 20
  // ceil(0.95 * 20) = 19, ceil(0.5 * 20) = 10, ceil(0.95 * 3) = 3, ceil(0.5 * 3) = 2.
  EXPECT_EQ(nearestRankPercentile(v.data(), 20, 95), 19);
  EXPECT_EQ(nearestRankPercentile(v.data(), 20, 50), 10);
  EXPECT_EQ(nearestRankPercentile(v.data(), 20, 100), 20);
  EXPECT_EQ(nearestRankPercentile(v.data(), 3, 95), 3);
  EXPECT_EQ(nearestRankPercentile(v.data(), 3, 50), 2);
  EXPECT_EQ(nearestRankPercentile(v.data(), 1, 95), 1);
}

TEST(EnsembleStats, PerCellStatisticsByHand) {
  const Heightfield g = test::flatHeightfield(3, 2, 1.0, 0.0);
  // Three realisations; cell 1 is passed by all three, cell 4 by one; realisation 2 stopped in
  // cell 5 (sample (2, 1) at (2, 1)).
  std::vector<RealisationResult> runs(3);
  runs[0].cells = {{1, 1000, 0.5, 2}, {4, 4000, 1.5, 5}};
  runs[1].cells = {{1, 3000, 0.1, 6}};
  runs[2].cells = {{1, 2000, 2.0, 4}};
  runs[2].state = RockState::kStopped;
  runs[2].end = Vec3(2.2, 0.9, 0);
  runs[1].state = RockState::kLeft;  // left: not deposited
  runs[1].end = Vec3(0.0, 0.0, 0);
  const auto layers = cellStatistics(g, runs);
  ASSERT_EQ(layers.size(), 9u);
  auto at = [&](const char* name, int cell) -> double {
    for (const StatLayer& l : layers)
      if (l.name == name) return l.values[static_cast<std::size_t>(cell)];
    ADD_FAILURE() << "no layer " << name;
    return NAN;
  };
  EXPECT_EQ(at("passages", 1), 3);
  EXPECT_EQ(at("reach_probability", 1), 1.0);
  EXPECT_EQ(at("reach_probability", 4), 1.0 / 3);
  EXPECT_EQ(at("passages", 0), 0);
  EXPECT_TRUE(std::isnan(at("energy_mean", 0)));
  EXPECT_DOUBLE_EQ(at("energy_mean", 1), 2.0);  // (1 + 3 + 2) / 3 kJ
  EXPECT_EQ(at("energy_p50", 1), 2.0);          // ceil(1.5) = 2nd of 1, 2, 3
  EXPECT_EQ(at("energy_p95", 1), 3.0);          // ceil(2.85) = 3rd
  EXPECT_EQ(at("energy_max", 1), 3.0);
  EXPECT_EQ(at("height_p95", 1), 2.0);
  EXPECT_EQ(at("speed_p95", 1), 6.0);
  EXPECT_EQ(at("energy_p95", 4), 4.0);
  EXPECT_EQ(at("deposited", 5), 1);
  EXPECT_EQ(at("deposited", 0), 0);
  // Convergence: the busiest cell first (cell 1, 3 passages), then cell 4 (1), then cell 0 (tie
  // at 0: lowest index); N = 3 gives the sizes 1 (3/2) and 3.
  const auto rows = convergence(g, runs, 3);
  ASSERT_EQ(rows.size(), 6u);
  EXPECT_EQ(rows[0].runs, 1);
  EXPECT_EQ(rows[0].cell, 1);
  EXPECT_EQ(rows[1].cell, 4);
  EXPECT_EQ(rows[2].cell, 0);
  EXPECT_EQ(rows[3].runs, 3);
  EXPECT_EQ(rows[3].reachProbability, 1.0);
  EXPECT_EQ(rows[3].energyP95, 3.0);
}

TEST(EnsembleSeeds, DependOnTheEnsembleSeedAndIndexOnly) {
  EXPECT_EQ(realisationSeed(7, 3), realisationSeed(7, 3));
  std::set<std::uint64_t> seen;
  for (std::uint64_t s = 0; s < 4; ++s)
    for (std::int64_t i = 0; i < 100; ++i) seen.insert(realisationSeed(s, i));
  EXPECT_EQ(seen.size(), 400u);  // no two (S, i) share a seed here
}

class EnsembleRunTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("voxfall_ensemble_unit_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    ASSERT_TRUE(test::writeChuteDem(dir_ / "chute.tif"));
  }
  void TearDown() override { fs::remove_all(dir_); }
  SceneSpec load(const std::string& ensemble, double duration = 1.0,
                 const std::string& ground = "") {
    test::writeChuteScene(dir_, ensemble, duration, ground);
    return loadScene((dir_ / "scene.toml").string());
  }
  fs::path dir_;
};

TEST_F(EnsembleRunTest, ReleasesLieInTheAreaOnTheLineOrOnThePoints) {
  // Area: a triangle; every release's centre of mass (x, y) inside it.
  {
    const Ensemble e(load(
        "shape = \"rock\"\nrelease = { area = [[1004, 5004], [1014, 5004], [1004, 5020]] }\n"));
    for (int i = 0; i < 40; ++i) {
      const Vec3 x = e.makeWorld(realisationSeed(1, i)).world->state(0).x;
      EXPECT_GE(x.x(), 4);
      EXPECT_GE(x.y(), 4);
      EXPECT_LE((x.x() - 4) / 10 + (x.y() - 4) / 16, 1 + 1e-12) << "outside the triangle";
      // drop_height 1 m (the default): the lowest point 1 m above the surface under it.
      EXPECT_GT(x.z(), e.dem().heightAt(x.x(), x.y()));
    }
  }
  // Line: on x = 5 between y = 6.3 and 17.7.
  {
    const Ensemble e(load(test::kChuteEnsemble));
    double yMin = 1e9, yMax = -1e9;
    for (int i = 0; i < 40; ++i) {
      const Vec3 x = e.makeWorld(realisationSeed(1, i)).world->state(0).x;
      EXPECT_DOUBLE_EQ(x.x(), 5.0);
      yMin = std::min(yMin, x.y());
      yMax = std::max(yMax, x.y());
    }
    EXPECT_GE(yMin, 6.3);
    EXPECT_LE(yMax, 17.7);
    EXPECT_GT(yMax - yMin, 5.0);  // spread along the line, not one spot
  }
  // Points: each release at one of them.
  {
    const Ensemble e(
        load("shape = \"rock\"\nrelease = { points = [[1005, 5007], [1009, 5015]] }\n"));
    int first = 0;
    for (int i = 0; i < 40; ++i) {
      const Vec3 x = e.makeWorld(realisationSeed(1, i)).world->state(0).x;
      const bool a = x.x() == 5 && x.y() == 7, b = x.x() == 9 && x.y() == 15;
      EXPECT_TRUE(a || b) << x.transpose();
      first += a;
    }
    EXPECT_GT(first, 5);
    EXPECT_LT(first, 35);
  }
}

TEST_F(EnsembleRunTest, ReleasesFromASourceRasterLieInItsSourceCells) {
  // Sources: DEM pixels (column 3, row 4 from the south) and (column 10, row 8), on a copy of
  // the chute's grid with every other value 0.
  test::ChuteDem c;
  ASSERT_TRUE(test::writeChuteDem(dir_ / "sources.tif", c));
  {
    GDALDatasetH ds = GDALOpen((dir_ / "sources.tif").c_str(), GA_Update);
    ASSERT_NE(ds, nullptr);
    std::vector<double> v(static_cast<std::size_t>(c.nx) * c.ny, 0.0);
    v[static_cast<std::size_t>(c.ny - 1 - 4) * c.nx + 3] = 1;  // GDAL rows from the north
    v[static_cast<std::size_t>(c.ny - 1 - 8) * c.nx + 10] = 7;
    ASSERT_EQ(GDALRasterIO(GDALGetRasterBand(ds, 1), GF_Write, 0, 0, c.nx, c.ny, v.data(), c.nx,
                           c.ny, GDT_Float64, 0, 0),
              CE_None);
    GDALClose(ds);
  }
  const Ensemble e(load("shape = \"rock\"\nrelease = { cells = \"sources.tif\" }\n"));
  int inFirst = 0;
  for (int i = 0; i < 40; ++i) {
    const Vec3 x = e.makeWorld(realisationSeed(1, i)).world->state(0).x;
    // World x of sample (i, j) is 1 + 2 i (DEM x0 = 1001 minus the offset 1000), y is 1 + 2 j.
    const bool a = std::abs(x.x() - 7) <= 1 && std::abs(x.y() - 9) <= 1;
    const bool b = std::abs(x.x() - 21) <= 1 && std::abs(x.y() - 17) <= 1;
    EXPECT_TRUE(a || b) << x.transpose();
    inFirst += a;
  }
  EXPECT_GT(inFirst, 5);
  EXPECT_LT(inFirst, 35);
  EXPECT_EQ(e.releaseAreas().size(), 2u);  // one square per source cell
  // A raster on another grid is an error naming the key.
  c.nx = 30;
  ASSERT_TRUE(test::writeChuteDem(dir_ / "sources.tif", c));
  try {
    const Ensemble bad(load("shape = \"rock\"\nrelease = { cells = \"sources.tif\" }\n"));
    ADD_FAILURE() << "a source raster off the DEM's grid was accepted";
  } catch (const InputError& err) {
    EXPECT_NE(std::string(err.what()).find("'release.cells' raster must lie on the DEM's grid"),
              std::string::npos)
        << err.what();
  }
}

TEST_F(EnsembleRunTest, ARealisationIsTheSameAloneAndOnTwoThreads) {
  const Ensemble e(load(test::kChuteEnsemble));
  const std::vector<std::int64_t> indices = {0, 1, 2, 3, 4};
  const auto threaded = runRealisations(e, indices, 9, 2, true, {}, {});
  ASSERT_EQ(threaded.size(), indices.size());
  for (std::size_t k = 0; k < indices.size(); ++k) {
    const RealisationResult alone = e.run(indices[k], realisationSeed(9, indices[k]), true);
    EXPECT_TRUE(threaded[k].complete);
    EXPECT_EQ(threaded[k].index, indices[k]);
    EXPECT_EQ(threaded[k].checksum, alone.checksum);
    ASSERT_EQ(threaded[k].path.size(), alone.path.size());
    EXPECT_TRUE(threaded[k].path.back().x == alone.path.back().x);
    ASSERT_EQ(threaded[k].cells.size(), alone.cells.size());
    for (std::size_t c = 0; c < alone.cells.size(); ++c) {
      EXPECT_EQ(threaded[k].cells[c].cell, alone.cells[c].cell);
      EXPECT_EQ(threaded[k].cells[c].energy, alone.cells[c].energy);
    }
  }
  EXPECT_NE(threaded[0].checksum, threaded[1].checksum);  // realisations differ
  // Serialised and back (the MPI gather): the same results.
  const auto back = deserializeResults(serializeResults(threaded));
  ASSERT_EQ(back.size(), threaded.size());
  for (std::size_t k = 0; k < back.size(); ++k) {
    EXPECT_EQ(back[k].checksum, threaded[k].checksum);
    EXPECT_EQ(back[k].cells.size(), threaded[k].cells.size());
    EXPECT_EQ(back[k].path.size(), threaded[k].path.size());
    EXPECT_TRUE(back[k].end == threaded[k].end);
  }
}

TEST_F(EnsembleRunTest, AStopRequestAbandonsRealisations) {
  const Ensemble e(load(test::kChuteEnsemble));
  const auto results = runRealisations(e, {0, 1, 2}, 1, 1, false, {}, [] { return true; });
  for (const RealisationResult& r : results) EXPECT_FALSE(r.complete);
}

TEST_F(EnsembleRunTest, MaterialRangesAreDrawnPerRealisation) {
  const Ensemble e(load(std::string(test::kChuteEnsemble) + "friction = [0.2, 0.9]\n"));
  std::set<double> restitution, friction;
  for (int i = 0; i < 10; ++i) {
    const RealisationWorld w = e.makeWorld(realisationSeed(1, i));
    ASSERT_TRUE(w.rockFall->def().ground);
    const GroundMaterial& m = w.rockFall->def().ground->materials[0];
    EXPECT_GE(m.restitution, 0.3);
    EXPECT_LT(m.restitution, 0.4);
    EXPECT_GE(m.friction, 0.2);
    EXPECT_LT(m.friction, 0.9);
    restitution.insert(m.restitution);
    friction.insert(m.friction);
  }
  EXPECT_EQ(restitution.size(), 10u);
  EXPECT_EQ(friction.size(), 10u);
}

// [ground] variability: each realisation perturbs the ground with a seed of its own, drawn from
// its realisation seed (so a realisation alone and on two threads is the same, bit for bit),
// and switching it on changes no other draw (the release point is the same). variability = 0
// is the scene without it, bit for bit.
TEST_F(EnsembleRunTest, PerCellVariabilityIsDrawnPerRealisationAndRepeats) {
  const Ensemble plain(load(test::kChuteEnsemble, 1.0));
  const Ensemble zero(load(test::kChuteEnsemble, 1.0, "variability = 0.0\n"));
  const Ensemble varied(load(test::kChuteEnsemble, 1.0, "variability = 0.1\n"));
  std::set<std::uint64_t> seeds;
  for (int i = 0; i < 5; ++i) {
    const RealisationWorld w = varied.makeWorld(realisationSeed(1, i));
    const GroundMap* ground = w.rockFall->def().ground.get();
    ASSERT_TRUE(ground);
    EXPECT_EQ(ground->variability, 0.1);
    EXPECT_EQ(ground->variabilitySeed,
              varied.makeWorld(realisationSeed(1, i)).rockFall->def().ground->variabilitySeed);
    seeds.insert(ground->variabilitySeed);
    EXPECT_TRUE(w.world->state(0).x == plain.makeWorld(realisationSeed(1, i)).world->state(0).x);
  }
  EXPECT_EQ(seeds.size(), 5u);
  const std::vector<std::int64_t> indices = {0, 1, 2};
  const auto threaded = runRealisations(varied, indices, 1, 2, false, {}, {});
  const auto zeros = runRealisations(zero, indices, 1, 1, false, {}, {});
  for (std::size_t k = 0; k < indices.size(); ++k) {
    const RealisationResult alone = varied.run(indices[k], realisationSeed(1, indices[k]), false);
    EXPECT_EQ(threaded[k].checksum, alone.checksum);
    const RealisationResult base = plain.run(indices[k], realisationSeed(1, indices[k]), false);
    EXPECT_EQ(zeros[k].checksum, base.checksum);
    EXPECT_NE(alone.checksum, base.checksum) << "the variability changed nothing";
  }
}

TEST_F(EnsembleRunTest, SubsetBakeHoldsEachRealisationsStateAtTheFrameTimes) {
  const Ensemble e(load(test::kChuteEnsemble, 2.0));
  const std::vector<std::int64_t> chosen = {3, 1};
  const Bake bake = ensembleBake(e, 5, chosen);
  ASSERT_EQ(bake.bodies.size(), 2u);
  EXPECT_FALSE(bake.summary.has_value());  // written as null (ensemble_command_test)
  const int frames = Recorder::frameCountFor(e.spec().fps, 2.0);
  ASSERT_EQ(bake.records.size(), static_cast<std::size_t>(frames));
  for (std::size_t b = 0; b < chosen.size(); ++b) {
    // The realisation alone, read by a Recorder (not by the bake's own loop), compared while
    // its rock is still moving.
    const RealisationWorld made = e.makeWorld(realisationSeed(5, chosen[b]));
    Recorder recorder(*made.world, e.spec().fps, 2.0);
    int compared = 0;
    for (int k = 0; k < frames; ++k) {
      const double t = k / e.spec().fps;
      recorder.advanceToFrame(k);
      if (made.rockFall->outcomes()[0].state != RockState::kMoving) break;
      const BodyState y = recorder.frameStates()[0];
      const BakeRecord& r = bake.records[static_cast<std::size_t>(k)];
      EXPECT_EQ(r.time, t);
      EXPECT_TRUE(r.states[b].x == y.x) << "body " << b << " frame " << k;
      EXPECT_TRUE(r.states[b].q.coeffs() == y.q.coeffs()) << "body " << b << " frame " << k;
      // And what the renderer reads back at the frame time.
      std::vector<char> active;
      EXPECT_TRUE(bake.statesAt(t, active)[b].x == y.x);
      ++compared;
    }
    EXPECT_GT(compared, 30);
    EXPECT_GT((bake.records[20].states[b].x - bake.records[0].states[b].x).norm(), 1.0);
  }
}

TEST_F(EnsembleRunTest, SubsetBakeEndsAtTheFrameWhereItsLastRealisationHasEnded) {
  // 120 s: every rock leaves the chute's foot long before (ensemble_command_test); the bake
  // must stop at the first frame by which all of them have ended, not hold them to 120 s.
  const Ensemble e(load(test::kChuteEnsemble, 120.0));
  const double fps = e.spec().fps;
  const std::vector<std::int64_t> chosen = {3, 1};
  int last = 0;
  for (const std::int64_t i : chosen) {
    // The realisation alone, step by step until its rock has ended: the first frame time at
    // or after the step that ended it (the bake's loop takes a step ending within
    // kTimeTolerance after a frame time with that frame).
    const RealisationWorld made = e.makeWorld(realisationSeed(5, i));
    const auto& w = made.world;
    while (made.rockFall->outcomes()[0].state == RockState::kMoving) w->stepNext();
    int k = 0;
    while (w->time() > k / fps + kTimeTolerance) ++k;
    ASSERT_LT(k, Recorder::frameCountFor(fps, 120.0) - 1) << "realisation " << i;
    last = std::max(last, k);
  }
  const Bake bake = ensembleBake(e, 5, chosen);
  ASSERT_EQ(bake.records.size(), static_cast<std::size_t>(last + 1));
  // The render counts frames by the bake scene's duration: the same count.
  EXPECT_EQ(Recorder::frameCountFor(bake.scene.fps, bake.scene.duration), last + 1);
  // One realisation cut off by the duration keeps the bake to it (the previous test's 2 s).
  const Ensemble cut(load(test::kChuteEnsemble, 2.0));
  EXPECT_EQ(ensembleBake(cut, 5, chosen).records.size(),
            static_cast<std::size_t>(Recorder::frameCountFor(cut.spec().fps, 2.0)));
}

TEST_F(EnsembleRunTest, SubsetBakeChecksumsAreThoseOfTheRealisationsRunAlone) {
  // The checksums the bake reports must be runs.csv's: Ensemble::run's, an independent loop
  // over the same realisation. 2.05 s is not a whole number of frames, and the rocks still
  // move then, so the steps after the last frame time count too; at 120 s every rock ends.
  for (const double duration : {2.05, 120.0}) {
    const Ensemble e(load(test::kChuteEnsemble, duration));
    const std::vector<std::int64_t> chosen = {3, 1, 6};
    std::vector<std::uint64_t> checksums;
    ensembleBake(e, 5, chosen, &checksums);
    ASSERT_EQ(checksums.size(), chosen.size());
    for (std::size_t b = 0; b < chosen.size(); ++b) {
      const RealisationResult r = e.run(chosen[b], realisationSeed(5, chosen[b]), false);
      EXPECT_EQ(checksums[b], r.checksum) << "duration " << duration << ", realisation " << b;
      if (duration < 3) {
        EXPECT_EQ(r.state, RockState::kMoving) << "the tail after the last frame is not tested";
        const double lastFrame =
            (Recorder::frameCountFor(e.spec().fps, duration) - 1) / e.spec().fps;
        EXPECT_GT(duration - lastFrame, 1e-3);
      }
    }
    EXPECT_NE(checksums[0], checksums[1]);
  }
}

}  // namespace
}  // namespace vf

// voxfall ensemble end to end on a small synthetic chute (tests/support/chute_dem.h): the
// outputs do not depend on --jobs, a realisation rerun alone is the same trajectory, the reach
// probability agrees with an independent count from the written paths, and bad [ensemble] input
// is one clear error. The rasters' georeference and the maps' window: ensemble_georef_test.
#include <fcntl.h>
#include <gdal.h>
#include <gtest/gtest.h>
#include <ogr_srs_api.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "render/output/png_writer.h"
#include "tests/support/chute_dem.h"
#include "tests/support/segment_square.h"
#include "tests/support/voxfall_command.h"

namespace {

namespace fs = std::filesystem;
using vf::test::readFile;
using vf::test::runVoxfall;

const std::string kExe = VOXFALL_EXE;
constexpr int kRuns = 8;

std::vector<std::string> lines(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) out.push_back(line);
  return out;
}

std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> out;
  std::istringstream in(line);
  for (std::string f; std::getline(in, f, ',');) out.push_back(f);
  return out;
}

class EnsembleCommandTest : public vf::test::ChuteFolderTest {
 protected:
  // Every output file of an output folder, by name: all but the journal, whose records are in
  // the order the realisations finished.
  std::map<std::string, std::string> files(const std::string& folder) const {
    std::map<std::string, std::string> out;
    for (const auto& e : fs::directory_iterator(dir_ / folder))
      if (e.path().filename() != "ensemble.journal")
        out[e.path().filename().string()] = readFile(e.path());
    return out;
  }
};

TEST_F(EnsembleCommandTest, OutputsAreTheSameBytesForOneAndTwoThreads) {
  vf::test::writeChuteScene(dir_, vf::test::kChuteEnsemble);
  const std::string common = "ensemble scene.toml --runs " + std::to_string(kRuns) +
                             " --seed 7 --converge --paths --maps -q";
  const auto one = runVoxfall(kExe, dir_, common + " --jobs 1 -o j1");
  ASSERT_EQ(one.code, 0) << one.err;
  const auto two = runVoxfall(kExe, dir_, common + " --jobs 2 -o j2");
  ASSERT_EQ(two.code, 0) << two.err;
  const auto a = files("j1"), b = files("j2");
  // 9 statistics x (GeoTIFF, ASCII, .prj, map PNG) + runs.csv, summary.json, converge.csv,
  // paths.csv, intensity.png, runout.png.
  EXPECT_EQ(a.size(), 9u * 4 + 6);
  EXPECT_TRUE(a.count("reach_probability.png") && a.count("runout.png"));
  // Cells no realisation reached show the grey hillshade, not the colour map's low end: on the
  // chute most of the map is unreached, so mid-grey pixels (R = G = B, 60..240, which viridis
  // never gives) must cover a large share of the image (axes and text are a few per cent).
  const vf::Image map = vf::readPng((dir_ / "j1" / "reach_probability.png").string());
  std::size_t grey = 0;
  for (std::size_t p = 0; p + 2 < map.rgb.size(); p += 3)
    if (map.rgb[p] == map.rgb[p + 1] && map.rgb[p + 1] == map.rgb[p + 2] && map.rgb[p] >= 60 &&
        map.rgb[p] <= 240)
      ++grey;
  EXPECT_GT(grey, map.rgb.size() / 3 / 5) << "under a fifth of the map shows the hillshade";
  ASSERT_EQ(a.size(), b.size());
  for (const auto& [name, bytes] : a) {
    ASSERT_TRUE(b.count(name)) << name;
    EXPECT_TRUE(bytes == b.at(name)) << name << " differs between --jobs 1 and --jobs 2";
  }
  EXPECT_EQ(lines(a.at("runs.csv")).size(), static_cast<std::size_t>(kRuns) + 1);
  // A different seed gives a different ensemble (the seed reaches the realisations).
  const auto other = runVoxfall(kExe, dir_, "ensemble scene.toml --runs 8 --seed 8 -q -o s8");
  ASSERT_EQ(other.code, 0) << other.err;
  EXPECT_NE(files("s8").at("runs.csv"), a.at("runs.csv"));
}

TEST_F(EnsembleCommandTest, RockFamiliesGiveTheSameBytesForOneAndTwoThreads) {
  // A generated EOTA block and a family of four natural rocks, drawn by weight: every variant
  // is built once before the threads start, so the outputs are the same bytes on 1 and 2.
  std::ofstream(dir_ / "scene.toml")
      << "[simulation]\nduration = 3.0\nlevel = 2\nrotation = \"midpoint\"\n"
         "[ground]\nheightfield = \"chute.tif\"\noffset = [-1000.0, -5000.0, 0.0]\n"
         "material = \"glacial_deposits\"\n"
         "[shapes.block]\nrock = { class = \"eota_221\", size = 0.8 }\ndensity = 2600\n"
         "[shapes.stones]\nrock = { class = \"elongated\", seeds = 4, volume = 0.1 }\n"
         "density = 2600\n"
         "[ensemble]\nshapes = [\"block\", \"stones\"]\nweights = [1, 2]\n"
         "release = { line = [[1005.0, 5006.3], [1005.0, 5017.7]] }\n"
         "velocity = { min = [1.0, -0.5, 0.0], max = [3.0, 0.5, 0.0] }\n";
  const std::string common = "ensemble scene.toml --runs 8 --seed 3 --paths -q";
  const auto one = runVoxfall(kExe, dir_, common + " --jobs 1 -o j1");
  ASSERT_EQ(one.code, 0) << one.err;
  const auto two = runVoxfall(kExe, dir_, common + " --jobs 2 -o j2");
  ASSERT_EQ(two.code, 0) << two.err;
  const auto a = files("j1"), b = files("j2");
  ASSERT_EQ(a.size(), b.size());
  for (const auto& [name, bytes] : a) {
    ASSERT_TRUE(b.count(name)) << name;
    EXPECT_TRUE(bytes == b.at(name)) << name << " differs between --jobs 1 and --jobs 2";
  }
  // runs.csv names each realisation's shape: the block or a variant of the family.
  std::set<std::string> shapes;
  const auto rows = lines(a.at("runs.csv"));
  ASSERT_EQ(rows.size(), 9u);
  for (std::size_t k = 1; k < rows.size(); ++k) shapes.insert(split(rows[k])[2]);
  for (const std::string& name : shapes)
    EXPECT_TRUE(name == "block" || name.rfind("stones#", 0) == 0) << name;
  EXPECT_GT(shapes.size(), 1u);
}

TEST_F(EnsembleCommandTest, RealisationAloneEqualsItsRunInsideTheEnsemble) {
  vf::test::writeChuteScene(dir_, vf::test::kChuteEnsemble);
  const auto all =
      runVoxfall(kExe, dir_, "ensemble scene.toml --runs 8 --jobs 2 --paths -q -o all");
  ASSERT_EQ(all.code, 0) << all.err;
  const auto alone =
      runVoxfall(kExe, dir_, "ensemble scene.toml --runs 8 --only 5 --paths -q -o alone");
  ASSERT_EQ(alone.code, 0) << alone.err;
  const auto rowsAll = lines(readFile(dir_ / "all" / "runs.csv"));
  const auto rowsAlone = lines(readFile(dir_ / "alone" / "runs.csv"));
  ASSERT_EQ(rowsAlone.size(), 2u);
  ASSERT_EQ(rowsAll.size(), 9u);
  EXPECT_EQ(rowsAlone[1], rowsAll[6]);  // row of realisation 5, checksum of every step included
  EXPECT_EQ(split(rowsAlone[1])[0], "5");
  // The path, every step, bit for bit (%.17g).
  std::vector<std::string> pathAll, pathAlone;
  for (const auto& l : lines(readFile(dir_ / "all" / "paths.csv")))
    if (l.rfind("5,", 0) == 0) pathAll.push_back(l);
  for (const auto& l : lines(readFile(dir_ / "alone" / "paths.csv")))
    if (l.rfind("5,", 0) == 0) pathAlone.push_back(l);
  EXPECT_GT(pathAll.size(), 100u);
  EXPECT_EQ(pathAll, pathAlone);
  // --only outside the ensemble is a usage error.
  const auto bad = runVoxfall(kExe, dir_, "ensemble scene.toml --runs 8 --only 8 -q -o bad");
  EXPECT_EQ(bad.code, 1);
  EXPECT_NE(bad.err.find("--only 8"), std::string::npos) << bad.err;
}

TEST_F(EnsembleCommandTest, ReachProbabilityEqualsAnIndependentCountFromThePaths) {
  vf::test::writeChuteScene(dir_, vf::test::kChuteEnsemble);
  const auto r = runVoxfall(kExe, dir_, "ensemble scene.toml --runs 8 --jobs 2 --paths -q -o p");
  ASSERT_EQ(r.code, 0) << r.err;
  // Paths per realisation, DEM coordinates.
  std::map<int, std::vector<std::pair<double, double>>> paths;
  const auto pathLines = lines(readFile(dir_ / "p" / "paths.csv"));
  for (std::size_t k = 1; k < pathLines.size(); ++k) {
    const auto f = split(pathLines[k]);
    paths[std::stoi(f[0])].emplace_back(std::stod(f[2]), std::stod(f[3]));
  }
  ASSERT_EQ(paths.size(), 8u);
  const vf::test::ChuteDem c;
  GDALAllRegister();
  GDALDatasetH ds = GDALOpen((dir_ / "p" / "reach_probability.asc").c_str(), GA_ReadOnly);
  ASSERT_NE(ds, nullptr);
  std::vector<double> reach(static_cast<std::size_t>(c.nx) * c.ny);
  ASSERT_EQ(GDALRasterIO(GDALGetRasterBand(ds, 1), GF_Read, 0, 0, c.nx, c.ny, reach.data(), c.nx,
                         c.ny, GDT_Float64, 0, 0),
            CE_None);
  GDALClose(ds);
  int cellsReached = 0;
  for (int row = 0; row < c.ny; ++row)
    for (int i = 0; i < c.nx; ++i) {
      const double x0 = c.west + i * c.cell, x1 = x0 + c.cell;
      const double y1 = c.north - row * c.cell, y0 = y1 - c.cell;
      int count = 0;
      for (const auto& [index, pts] : paths) {
        bool met = false;
        for (std::size_t k = 0; k < pts.size() && !met; ++k) {
          const auto& a = pts[k > 0 ? k - 1 : 0];
          met = vf::test::segmentMeetsSquare(a.first, a.second, pts[k].first, pts[k].second, x0, x1,
                                             y0, y1);
        }
        count += met ? 1 : 0;
      }
      cellsReached += count > 0;
      // Written with 10 significant digits: k / 8 is exact in them.
      EXPECT_NEAR(reach[static_cast<std::size_t>(row) * c.nx + i], count / 8.0, 1e-12)
          << "cell column " << i << ", row " << row << " from the north";
    }
  EXPECT_GT(cellsReached, 20);  // the rocks went down the chute, not nowhere
}

TEST_F(EnsembleCommandTest, ReleaseAreaOutsideTheDemIsAnErrorNamingTheKey) {
  vf::test::writeChuteScene(
      dir_,
      "shape = \"rock\"\n"
      "release = { area = [[1004.0, 5006.0], [1500.0, 5006.0], [1004.0, 5018.0]] }\n");
  const auto r = runVoxfall(kExe, dir_, "ensemble scene.toml --runs 4 -q -o bad");
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find("scene.toml:15:"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("'release.area[1]' (1500.000, 5006.000) lies outside the DEM"),
            std::string::npos)
      << r.err;
  EXPECT_FALSE(fs::exists(dir_ / "bad" / "runs.csv"));
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
}

TEST_F(EnsembleCommandTest, MalformedEnsembleKeysAreClearErrors) {
  const std::pair<std::string, std::string> cases[] = {
      {"shape = \"rock\"\nrelase = { points = [[4.0, 6.0]] }\n",
       "scene.toml:15:1: unknown key 'relase' in [ensemble]; did you mean 'release'?"},
      {"shape = \"rock\"\nrelease = { points = [[4.0, 6.0]] }\nrestitution = [0.5, 0.2]\n",
       "scene.toml:16:15: 'restitution' must be [lo, hi] with lo <= hi"},
      {"shape = \"rok\"\nrelease = { points = [[4.0, 6.0]] }\n",
       "scene.toml:14:9: unknown shape 'rok'; did you mean 'rock'?"},
      {"shape = \"rock\"\nrelease = { area = [[4.0, 6.0], [5.0, 6.0]] }\n",
       "'release.area' must be an array of at least 3 [x, y] points"},
      {"shape = \"rock\"\nrelease = { points = [[4.0, 6.0]] }\nheight_classes = [2.0, 1.0]\n",
       "scene.toml:16:24: 'height_classes' must be ascending, got 1 after 2"},
      {"shape = \"rock\"\nrelease = { points = [[4.0, 6.0]] }\nheight_classes = [0.0]\n",
       "scene.toml:16:19: 'height_classes[0]' must be > 0 m, got 0"},
      {"shape = \"rock\"\nrelease = { points = [[4.0, 6.0]] }\nheight_classes = []\n",
       "'height_classes' must be an array of 1 to 5 ascending limits in m"},
      {"shape = \"rock\"\nrelease = { points = [[4.0, 6.0]] }\nheight_classes = [1, 2, 3, 4, "
       "5, 6]\n",
       "'height_classes' must be an array of 1 to 5 ascending limits in m"},
  };
  for (const auto& [table, message] : cases) {
    vf::test::writeChuteScene(dir_, table);
    const auto r = runVoxfall(kExe, dir_, "ensemble scene.toml --runs 2 -q -o bad");
    EXPECT_EQ(r.code, 1) << table;
    EXPECT_NE(r.err.find(message), std::string::npos) << r.err;
  }
}

// --seed takes the whole range of a 64-bit seed and nothing else: the option parser's unsigned
// conversion alone takes "-1" and 2^64 as 2^64 - 1, silently.
TEST_F(EnsembleCommandTest, SeedOutsideItsRangeIsAUsageError) {
  vf::test::writeChuteScene(dir_, vf::test::kChuteEnsemble);
  for (const std::string seed : {"-1", "18446744073709551616", "1e3", "7x"}) {
    const auto r = runVoxfall(kExe, dir_, "ensemble scene.toml --runs 1 -q -o bad --seed " + seed);
    EXPECT_EQ(r.code, 2) << seed;
    EXPECT_NE(r.err.find("--seed: must be an integer from 0 to 18446744073709551615, got " + seed),
              std::string::npos)
        << r.err;
    EXPECT_FALSE(fs::exists(dir_ / "bad")) << seed;
  }
  const auto top = runVoxfall(kExe, dir_,
                              "ensemble scene.toml --runs 1 -q -o top --seed "
                              "18446744073709551615");
  ASSERT_EQ(top.code, 0) << top.err;
  EXPECT_NE(readFile(dir_ / "top" / "summary.json").find("\"seed\": 18446744073709551615"),
            std::string::npos);
}

TEST_F(EnsembleCommandTest, SubsetVideoIsTheRenderOfItsBake) {
  // --video-runs writes the subset's bake and renders it: trajectories.mp4 must be the very
  // MP4 that `voxfall render` makes of that bake (the encoder is deterministic for a setting).
  vf::test::writeChuteScene(
      dir_, std::string(vf::test::kChuteEnsemble) + "[output]\nwidth = 160\nheight = 120\n");
  const auto r = runVoxfall(kExe, dir_, "ensemble scene.toml --runs 4 --video-runs 3 -q -o v");
  ASSERT_EQ(r.code, 0) << r.err;
  ASSERT_TRUE(fs::exists(dir_ / "v" / "trajectories.mp4"));
  const auto again = runVoxfall(kExe, dir_, "render v/ensemble_subset.bake -o again.mp4 -q");
  ASSERT_EQ(again.code, 0) << again.err;
  // The realisations were each stepped alone: the header has no run summary, and the render
  // says so rather than printing a summary of zeros (once it printed "checksum 0000000000000000").
  const std::string bake = readFile(dir_ / "v" / "ensemble_subset.bake");
  EXPECT_NE(bake.find("\"summary\":null"), std::string::npos);
  EXPECT_NE(again.out.find("frames of 3 ensemble realisations"), std::string::npos) << again.out;
  EXPECT_EQ(again.out.find("  checksum "), std::string::npos) << again.out;  // printSummary's line
  EXPECT_EQ(again.out.find("steps simulated"), std::string::npos) << again.out;
  const std::string video = readFile(dir_ / "v" / "trajectories.mp4");
  EXPECT_GT(video.size(), 1000u);
  EXPECT_TRUE(video == readFile(dir_ / "again.mp4"));
  const auto frame = runVoxfall(
      kExe, dir_, "render v/ensemble_subset.bake --frames 30:30 --size 160x120 -o f.png -q");
  ASSERT_EQ(frame.code, 0) << frame.err;
  EXPECT_GT(fs::file_size(dir_ / "f.png"), 1000u);
}

TEST_F(EnsembleCommandTest, RegressCaseIsTheSubsetBakeAndChecksTheRealisations) {
  // A regress case with `runs = 3` must be exactly what `voxfall ensemble --video-runs 3` makes:
  // its checksums are runs.csv's for realisations 0-2, and its frames are `voxfall render`'s
  // frames of ensemble_subset.bake, pixel for pixel. Both come through another path (Ensemble::run
  // over four realisations; the bake written to disk and read back).
  vf::test::writeChuteScene(
      dir_, std::string(vf::test::kChuteEnsemble) + "[output]\nwidth = 160\nheight = 120\n");
  fs::create_directories(dir_ / "s");
  std::ofstream(dir_ / "s" / "suite.toml")
      << "[[case]]\nname = \"chute\"\nscene = \"../scene.toml\"\nruns = 3\n"
         "frames = [0, 30, 60]\n";
  const auto update = runVoxfall(kExe, dir_, "regress s --update -o rep");
  ASSERT_EQ(update.code, 0) << update.out << update.err;
  EXPECT_NE(update.out.find("chute: 3 frames at 160x120, 3 ensemble realisations"),
            std::string::npos)
      << update.out;

  const auto ens = runVoxfall(kExe, dir_, "ensemble scene.toml --runs 4 --video-runs 3 -q -o v");
  ASSERT_EQ(ens.code, 0) << ens.err;
  const std::vector<std::string> rows = lines(readFile(dir_ / "v" / "runs.csv"));
  ASSERT_EQ(rows.size(), 5u);
  ASSERT_EQ(split(rows[0]).back(), "checksum");
  std::string expected;
  for (int i = 1; i <= 3; ++i) expected += (i > 1 ? " " : "") + split(rows[i]).back();
  EXPECT_EQ(readFile(dir_ / "s" / "chute" / "checksum.txt"), expected + "\n");
  for (const int k : {0, 30, 60}) {
    const std::string png = "f" + std::to_string(k) + ".png";
    const auto frame = runVoxfall(kExe, dir_,
                                  "render v/ensemble_subset.bake --frames " + std::to_string(k) +
                                      ":" + std::to_string(k) + " -o " + png + " -q");
    ASSERT_EQ(frame.code, 0) << frame.err;
    char golden[32];
    std::snprintf(golden, sizeof golden, "frame_%04d.png", k);
    // The pixels, byte for byte (render compresses frames faster than regress goldens).
    EXPECT_TRUE(vf::readPng((dir_ / png).string()).rgb ==
                vf::readPng((dir_ / "s" / "chute" / golden).string()).rgb)
        << golden;
  }

  const auto pass = runVoxfall(kExe, dir_, "regress s -o rep");
  EXPECT_EQ(pass.code, 0) << pass.out;

  // One realisation's golden checksum altered: the failure names that realisation alone.
  std::vector<std::string> words;
  std::istringstream in(expected);
  for (std::string w; in >> w;) words.push_back(w);
  words[1] = "0123456789abcdef";
  std::ofstream(dir_ / "s" / "chute" / "checksum.txt")
      << words[0] << " " << words[1] << " " << words[2] << "\n";
  const auto one = runVoxfall(kExe, dir_, "regress s -o rep");
  EXPECT_EQ(one.code, 1);
  EXPECT_NE(one.out.find("the physics changed (realisations 1) "), std::string::npos) << one.out;

  // The scene's physics changed (the ground's restitution range): every realisation differs.
  std::string bouncier = vf::test::kChuteEnsemble;
  const std::size_t at = bouncier.find("restitution = [0.3, 0.4]");
  ASSERT_NE(at, std::string::npos) << "kChuteEnsemble changed";
  bouncier.replace(at, 24, "restitution = [0.6, 0.7]");
  vf::test::writeChuteScene(dir_, bouncier + "[output]\nwidth = 160\nheight = 120\n");
  std::ofstream(dir_ / "s" / "chute" / "checksum.txt") << expected << "\n";
  const auto changed = runVoxfall(kExe, dir_, "regress s -o rep");
  EXPECT_EQ(changed.code, 1);
  EXPECT_NE(changed.out.find("the physics changed (realisations 0, 1, 2) "), std::string::npos)
      << changed.out;
}

TEST_F(EnsembleCommandTest, AnInterruptedEnsembleWritesItsCompleteRealisationsAndSaysSo) {
  vf::test::writeChuteScene(dir_, vf::test::kChuteEnsemble, 10.0);
  const pid_t child = vf::test::startVoxfall(
      kExe, dir_, {"ensemble", "scene.toml", "--runs", "100000", "--jobs", "2", "-q", "-o", "int"});
  // Long enough for some realisations (tens of milliseconds each) to finish, on a busy machine
  // too (2 s can be too short in a `ctest -j2` run of the whole suite; 4 s holds beside the
  // heaviest tests); 100000 of them take minutes, so the run is still going.
  std::this_thread::sleep_for(std::chrono::seconds(4));
  ::kill(child, SIGINT);
  int status = 0;
  ::waitpid(child, &status, 0);
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 130);
  const auto rows = lines(readFile(dir_ / "int" / "runs.csv"));
  ASSERT_GE(rows.size(), 2u) << "no realisation finished in 4 s";
  // The complete realisations, in index order (not necessarily 0 .. k-1: a slow one may still
  // have been running), each the row it has in an ensemble that ran it to the end.
  std::vector<std::string> indices;
  for (std::size_t i = 1; i < rows.size(); ++i) indices.push_back(split(rows[i])[0]);
  for (std::size_t i = 1; i < indices.size(); ++i)
    EXPECT_LT(std::stoll(indices[i - 1]), std::stoll(indices[i]));
  const auto ref = runVoxfall(
      kExe, dir_,
      "ensemble scene.toml -q -o ref --runs " + std::to_string(std::stoll(indices.back()) + 1));
  ASSERT_EQ(ref.code, 0) << ref.err;
  std::map<std::string, std::string> refRows;
  for (const std::string& row : lines(readFile(dir_ / "ref" / "runs.csv")))
    refRows[split(row)[0]] = row;
  for (std::size_t i = 1; i < rows.size(); ++i) EXPECT_EQ(rows[i], refRows[indices[i - 1]]);
  // The summary says the run was interrupted, and which realisations the files hold.
  const std::string summary = readFile(dir_ / "int" / "summary.json");
  EXPECT_NE(summary.find("\"signal\": \"SIGINT\""), std::string::npos) << summary;
  EXPECT_NE(summary.find("\"runs\": " + std::to_string(rows.size() - 1)), std::string::npos);
  EXPECT_NE(readFile(dir_ / "ref" / "summary.json").find("\"interrupted\": null"),
            std::string::npos);
}

// The number of runs.csv rows whose state is `state`.
int countState(const std::string& csv, const std::string& state) {
  const auto rows = lines(csv);
  if (rows.empty()) return -1;
  const auto header = split(rows[0]);
  const auto column = std::find(header.begin(), header.end(), "state") - header.begin();
  int n = 0;
  for (std::size_t k = 1; k < rows.size(); ++k) {
    const auto fields = split(rows[k]);
    if (static_cast<std::size_t>(column) < fields.size() && fields[column] == state) ++n;
  }
  return n;
}

TEST_F(EnsembleCommandTest, RealisationsCutOffByTheDurationAreAWarningWithTheirCount) {
  // 2 s: no rock gets down the 120 m chute or stops on its 35 degrees (steeper than the glacial
  // deposits' rolling friction, atan(0.65) = 33 degrees), so every realisation is cut off.
  vf::test::writeChuteScene(dir_, vf::test::kChuteEnsemble, 2.0);
  const auto cut = runVoxfall(kExe, dir_, "ensemble scene.toml --runs 4 -q -o cut");
  ASSERT_EQ(cut.code, 0) << cut.err;
  const int moving = countState(readFile(dir_ / "cut" / "runs.csv"), "moving");
  EXPECT_EQ(moving, 4);
  EXPECT_NE(cut.err.find("warning: " + std::to_string(moving) +
                         " of 4 realisations ended at the scene's duration (2 s) with the rock "
                         "still moving"),
            std::string::npos)
      << cut.err;
  // Long enough for every rock to leave the chute's foot (edge "remove"): no warning.
  vf::test::writeChuteScene(dir_, vf::test::kChuteEnsemble, 120.0);
  const auto whole = runVoxfall(kExe, dir_, "ensemble scene.toml --runs 4 -q -o whole");
  ASSERT_EQ(whole.code, 0) << whole.err;
  EXPECT_EQ(countState(readFile(dir_ / "whole" / "runs.csv"), "moving"), 0);
  EXPECT_EQ(whole.err.find("warning"), std::string::npos) << whole.err;
}

TEST_F(EnsembleCommandTest, ExistingOutputsNeedMinusY) {
  vf::test::writeChuteScene(dir_, vf::test::kChuteEnsemble);
  ASSERT_EQ(runVoxfall(kExe, dir_, "ensemble scene.toml --runs 2 -q -o o").code, 0);
  const auto again = runVoxfall(kExe, dir_, "ensemble scene.toml --runs 2 -q -o o");
  EXPECT_EQ(again.code, 1);
  // The journal is the first output checked: its message points at --resume as well as -y.
  EXPECT_NE(again.err.find("o/ensemble.journal: already exists: an ensemble ran into this folder"),
            std::string::npos)
      << again.err;
  EXPECT_EQ(runVoxfall(kExe, dir_, "ensemble scene.toml --runs 2 -q -o o -y").code, 0);
}

}  // namespace

// voxfall's simulation benchmark (Google Benchmark). Build and run:
//   cmake --build build --target sim_bench && build/tests/bench/sim_bench
// Rows:
//   Scene/<name>/<level>/<ext>/<threads>: a whole run of scenes/<name>.toml (the same scene
//     files the CLI and the tests use) at voxel level Lv (every shape) with the eq.-20 step;
//     ext 0 is the paper's method, ext 1 adds contact reduction and sleeping (README,
//     "Performance"). Counters: wall seconds per simulated second (sec_per_sim_s) and its split
//     into stepping (step_s, the sum of the per-stage timers of StepStats) and the per-frame
//     true-mesh diagnostics (diag_s, timed around World::measure; diag_pct, their share of the
//     run, the rest being frame states and the timers themselves); the share of each stage of the
//     step (pct_*); steps, sphere tests, leaf contacts and contacts after reduction per step, mean
//     bodies awake (StepStats::awake) and asleep per step; the label carries the trajectory
//     checksum, so every benchmark run is also a determinism check (it must not change with the
//     thread count).
//   Rockfall/<n>/<threads>: n rocks released together over the cliff terrain
//     (scenes/cliff.toml's shapes and ground) at level 3 with reduction and sleeping, 4
//     simulated seconds. Adds cpu_per_sim_s (CPU seconds of the whole process, every thread,
//     per simulated second, scene building excluded: the figure to read on a shared machine),
//     cpu_us_per_rock_step (the same per rock and step: flat if the cost is linear in the
//     rocks at a given step) and pairs_per_step. Run with --benchmark_repetitions=3 for medians.
//   RockfallClearance/<n>/<threads>: the same with `step = "clearance"` (solve/time_step.h).
//   RockfallWide/<n>/<threads>: Rockfall at a constant density: one layer of rocks on the cliff
//     widened (mirrored copies along y) as far as the rocks need; the scale curve without the
//     deepening pile. Up to 1,392 rocks it is Rockfall/<n> itself (the same checksum).
//   SceneClearance/crosses/<level>/1/1: the crosses with the extensions and the clearance step.
//   SceneFile/rockfall/<threads>: scenes/rockfall.toml as it is (20 rocks on the Tyrol DEM's 5 m
//     cells, its own level, step rule and extensions), with the Scene rows' counters.
//   TreeBuild/<level>: voxel sphere tree of a 100k-triangle closed mesh (a bumpy sphere);
//   TreeBuild1M/7: of a 1M-triangle one at level 7, with the tree's memory.
//   DiagnosticsBuild1M: what the true-mesh diagnostics build for the same mesh (the triangle
//     hierarchy and the side grid), with their memory.
//   LoadDem/<file>: loading a DEM through GDAL: the 520 x 387 Tyrol grid as the repository's
//     Float64 GeoTIFF, and as an ESRI ASCII grid (VOXFALL_BENCH_ASCII_DEM, if set, names one,
//     e.g. the AvaFrame original).
#include <benchmark/benchmark.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>
#include <utility>

#include "sim/geometry/mesh_bvh.h"
#include "sim/recorder.h"
#include "sim/scene/scene.h"
#include "sim/shape/heightfield.h"
#include "sim/shape/side_grid.h"
#include "sim/shape/sphere_tree.h"

namespace {

std::string scenePath(const std::string& name) {
  return std::string(VOXFALL_SOURCE_DIR) + "/scenes/" + name + ".toml";
}

double stepSeconds(const vf::RunStats& t) {
  return t.secondsStepSize + t.secondsPairs + t.secondsContacts + t.secondsSolve +
         t.secondsIntegrate + t.secondsSleep + t.secondsRelease;
}

// CPU time of the whole process (all threads), s.
double processCpuSeconds() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

// Runs `spec` through all its frames (as `voxfall simulate` does) and reports the counters.
// Returns the process CPU seconds of the (last) run.
double runSpec(benchmark::State& state, vf::SceneSpec spec) {
  spec.stageTimes = true;  // the pct_* counters (a few per cent slower on tiny scenes)
  vf::RunSummary summary;
  double wall = 0, cpu = 0;
  for (auto _ : state) {
    state.PauseTiming();
    vf::BuiltScene built = vf::buildScene(spec);  // shape building is not the step's cost
    state.ResumeTiming();
    const double cpu0 = processCpuSeconds();
    vf::Recorder recorder(*built.world, spec.fps, spec.duration);
    for (int k = 0; k < recorder.frameCount(); ++k) recorder.advanceToFrame(k);
    summary = recorder.summary();
    wall = summary.wallSeconds;
    cpu = processCpuSeconds() - cpu0;
  }
  const vf::RunStats& t = summary.totals;
  const double step = stepSeconds(t);
  const double steps = static_cast<double>(t.steps);
  state.counters["sec_per_sim_s"] = benchmark::Counter(
      spec.duration, benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
  state.counters["step_s"] = step;
  state.counters["diag_s"] = summary.diagnosticsSeconds;
  state.counters["diag_pct"] = wall > 0 ? 100 * summary.diagnosticsSeconds / wall : 0;
  const std::pair<const char*, double> stages[] = {
      {"pct_pairs", t.secondsPairs},
      {"pct_narrow", t.secondsContacts},  // with the contact reduction, made there
      {"pct_solve", t.secondsSolve},
      {"pct_integrate", t.secondsIntegrate},
      {"pct_other", t.secondsStepSize + t.secondsSleep + t.secondsRelease}};
  for (const auto& [name, seconds] : stages)
    state.counters[name] = step > 0 ? 100 * seconds / step : 0;
  state.counters["steps"] = steps;
  state.counters["pairs_per_step"] = static_cast<double>(t.pairs) / steps;
  state.counters["cpu_per_sim_s"] = cpu / spec.duration;
  state.counters["tests_per_step"] = static_cast<double>(t.sphereTests) / steps;
  state.counters["leaf_contacts_per_step"] = static_cast<double>(t.leafContacts) / steps;
  state.counters["passes_per_step"] = static_cast<double>(t.solverPasses) / steps;
  state.counters["pct_pairs_by_candidates"] =
      100.0 * static_cast<double>(t.pairsByCandidates) /
      static_cast<double>(std::max<std::uint64_t>(1, t.pairsByCandidates + t.pairsByDescent));
  state.counters["contacts_per_step"] = static_cast<double>(t.contacts) / steps;
  state.counters["asleep_per_step"] = static_cast<double>(t.sleepingBodySteps) / steps;
  state.counters["awake_per_step"] = static_cast<double>(t.awakeBodySteps) / steps;
  state.counters["max_pen_mm"] =
      1e3 * std::max(summary.maxPenetrationBodyBody, summary.maxPenetrationBodyGround);
  state.SetLabel("checksum " + summary.checksumHex());
  return cpu;
}

// `clearance`: the clearance step rule (solve/time_step.h) instead of eq. 20.
void runScene(benchmark::State& state, const std::string& name, bool clearance = false) {
  vf::SceneSpec spec = vf::loadScene(scenePath(name));
  spec.level = static_cast<int>(state.range(0));
  for (vf::ShapeSpec& shape : spec.shapes) shape.level.reset();  // as `--level` does
  spec.contactReduction = spec.sleep = state.range(1) != 0;
  spec.step = clearance ? vf::StepRule::clearance() : vf::StepRule::eq20();
  spec.threads = static_cast<int>(state.range(2));
  runSpec(state, spec);
}

// A scene file run as `voxfall simulate` runs it: its own level, step rule and extensions; only
// the thread count comes from the row.
void runSceneFile(benchmark::State& state, const std::string& name) {
  vf::SceneSpec spec = vf::loadScene(scenePath(name));
  spec.threads = static_cast<int>(state.range(0));
  runSpec(state, spec);
}

// The cliff terrain widened along y to `copies` times its width, mirrored at every seam so
// that the surface stays continuous (row j of the wide grid is row m(j) of the cliff, m folding
// j back and forth over 0..ny-1); written as an ESRI ASCII grid with the header of
// scenes/terrain/cliff.asc (corner 0, 0; its cell size), so that one copy is the cliff itself,
// sample for sample (Rockfall and RockfallWide give the same checksum up to 1,392 rocks, which
// checks it). Returns the file's path, in the temporary directory (named by the process, so
// that two benchmark runs do not share it; the caller removes it).
std::string widenedCliff(const std::string& cliffPath, int copies) {
  const vf::Heightfield cliff = vf::loadDem(cliffPath);
  const int period = 2 * (cliff.ny - 1);
  const int ny = copies * (cliff.ny - 1) + 1;
  const std::string path =
      (std::filesystem::temp_directory_path() /
       ("voxfall_bench_cliff_x" + std::to_string(copies) + "_" + std::to_string(getpid()) + ".asc"))
          .string();
  std::ofstream out(path);
  out << "ncols " << cliff.nx << "\nnrows " << ny << "\nxllcorner 0\nyllcorner 0\ncellsize "
      << cliff.cell << "\nNODATA_value -9999\n";
  out.precision(17);
  for (int row = 0; row < ny; ++row) {  // the file's first row is the northernmost
    const int j = ny - 1 - row, m = j % period;
    const int source = m < cliff.ny ? m : period - m;
    for (int i = 0; i < cliff.nx; ++i)
      out << cliff.at(i, source) << (i + 1 < cliff.nx ? ' ' : '\n');
  }
  if (!out.flush()) throw std::runtime_error("cannot write " + path);
  return path;
}

// n rocks released at t = 0 over the cliff terrain, one per 0.8 m grid cell (48 along x, 29
// along y on the cliff's 24 m) and layer by layer upwards, each dropped 0.3 m onto what lies
// below it (drop_height); Lv 3, reduction and sleeping, 4 simulated seconds. With `clearance`,
// the clearance step rule (an extension) instead of eq. 20. With `wide`, at a constant density
// instead: one layer of rocks over as many widened copies of the cliff (above) as it needs, so
// that a rock has the neighbourhood it has at 1,000 rocks whatever n is. Up to 1,392 rocks (one
// copy) both are the same run (the same checksum); beyond, the plain one piles the rocks into
// layers on the one cliff.
void rockfall(benchmark::State& state, bool clearance, bool wide) {
  constexpr int kRowsPerCopy = 29, kColumns = 48;
  vf::SceneSpec spec = vf::loadScene(scenePath("cliff"));
  const int n = static_cast<int>(state.range(0));
  const int copies = wide ? (n + kColumns * kRowsPerCopy - 1) / (kColumns * kRowsPerCopy) : 1;
  if (wide) spec.terrainPath = widenedCliff(spec.terrainPath, copies);
  spec.level = 3;
  spec.duration = 4.0;
  spec.contactReduction = spec.sleep = true;
  spec.step = clearance ? vf::StepRule::clearance() : vf::StepRule::eq20();
  spec.emitters.resize(1);
  vf::EmitterSpec& e = spec.emitters[0];
  e.count = n;
  e.start = 0;
  e.interval = 0;
  e.positions.clear();
  for (int j = 0; j < kRowsPerCopy * copies; ++j)
    for (int i = 0; i < kColumns; ++i)
      e.positions.push_back(vf::Vec3(0.4 + 0.8 * i, 0.8 + 0.8 * j, 12));
  e.dropHeight = 0.3;
  e.velocity = vf::Vec3(0.5, 0, 0);
  spec.camera.followBody.reset();
  spec.threads = static_cast<int>(state.range(1));
  const double cpu = runSpec(state, spec);
  if (wide) std::filesystem::remove(spec.terrainPath);
  state.counters["rocks"] = n;
  if (wide) state.counters["copies"] = copies;
  state.counters["cpu_us_per_rock_step"] = 1e6 * cpu / (state.counters["steps"] * n);
}

void loadDem(benchmark::State& state, const std::string& path) {
  for (auto _ : state) benchmark::DoNotOptimize(vf::loadDem(path).z.data());
}

// A closed UV sphere of radius ~1 with a bumpy surface: rows x cols quads, two poles.
vf::TriMesh bumpySphere(int rows, int cols) {
  vf::TriMesh m;
  auto radius = [](double th, double ph) {
    return 1.0 + 0.08 * std::sin(5 * th) * std::cos(7 * ph) + 0.03 * std::sin(17 * th + 3 * ph);
  };
  m.vertices.push_back(vf::Vec3(0, 0, radius(0, 0)));
  for (int i = 1; i < rows; ++i) {
    const double th = M_PI * i / rows;
    for (int j = 0; j < cols; ++j) {
      const double ph = 2 * M_PI * j / cols;
      const double r = radius(th, ph);
      m.vertices.push_back(vf::Vec3(r * std::sin(th) * std::cos(ph),
                                    r * std::sin(th) * std::sin(ph), r * std::cos(th)));
    }
  }
  m.vertices.push_back(vf::Vec3(0, 0, -radius(M_PI, 0)));
  const auto ring = [&](int i, int j) {
    return static_cast<std::uint32_t>(1 + (i - 1) * cols + (j % cols));
  };
  const auto south = static_cast<std::uint32_t>(m.vertices.size() - 1);
  for (int j = 0; j < cols; ++j) m.triangles.push_back({0, ring(1, j), ring(1, j + 1)});
  for (int i = 1; i < rows - 1; ++i)
    for (int j = 0; j < cols; ++j) {
      m.triangles.push_back({ring(i, j), ring(i + 1, j), ring(i + 1, j + 1)});
      m.triangles.push_back({ring(i, j), ring(i + 1, j + 1), ring(i, j + 1)});
    }
  for (int j = 0; j < cols; ++j)
    m.triangles.push_back({south, ring(rows - 1, j + 1), ring(rows - 1, j)});
  return m;
}

void treeBuildOf(benchmark::State& state, const vf::TriMesh& mesh) {
  std::size_t leaves = 0, bytes = 0;
  for (auto _ : state) {
    const vf::SphereTree tree = vf::buildSphereTree(mesh, static_cast<int>(state.range(0)));
    leaves = tree.leaves().centers.size();
    bytes = tree.memoryBytes();
    benchmark::DoNotOptimize(leaves);
  }
  state.counters["triangles"] = static_cast<double>(mesh.triangles.size());
  state.counters["leaf_spheres"] = static_cast<double>(leaves);
  state.counters["tree_MB"] = static_cast<double>(bytes) / 1e6;
}

void treeBuild(benchmark::State& state) {
  treeBuildOf(state, bumpySphere(200, 251));  // 2 * 251 * 199 = 99,898 triangles
}

void treeBuild1M(benchmark::State& state) {
  treeBuildOf(state, bumpySphere(708, 708));  // 2 * 708 * 707 = 1,001,112 triangles
}

void diagnosticsBuild1M(benchmark::State& state) {
  const vf::TriMesh mesh = bumpySphere(708, 708);
  std::size_t bvhBytes = 0, gridBytes = 0;
  double gridSeconds = 0;
  for (auto _ : state) {
    const vf::MeshBvh bvh(mesh);
    const double start = processCpuSeconds();
    const vf::SideGrid grid(mesh, bvh);
    gridSeconds = processCpuSeconds() - start;
    bvhBytes = bvh.memoryBytes();
    gridBytes = grid.memoryBytes();
  }
  state.counters["triangles"] = static_cast<double>(mesh.triangles.size());
  state.counters["bvh_MB"] = static_cast<double>(bvhBytes) / 1e6;
  state.counters["grid_MB"] = static_cast<double>(gridBytes) / 1e6;
  state.counters["grid_s"] = gridSeconds;
}

}  // namespace

BENCHMARK_CAPTURE(runScene, cubes, std::string("cubes"))
    ->Name("Scene/cubes")
    ->ArgsProduct({{2, 3, 4}, {0, 1}, {1}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK_CAPTURE(runScene, blocks, std::string("blocks"))
    ->Name("Scene/blocks")
    ->ArgsProduct({{2, 3, 4}, {0, 1}, {1}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK_CAPTURE(runScene, highpoly, std::string("highpoly"))
    ->Name("Scene/highpoly")
    ->ArgsProduct({{2, 3, 4}, {0, 1}, {1}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK_CAPTURE(runScene, stack, std::string("stack"))
    ->Name("Scene/stack")
    ->ArgsProduct({{2, 3, 4}, {0, 1}, {1}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK_CAPTURE(runScene, crosses, std::string("crosses"))
    ->Name("Scene/crosses")
    ->ArgsProduct({{2, 3, 4}, {0, 1}, {1}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK_CAPTURE(runScene, barrel, std::string("barrel"))
    ->Name("Scene/barrel")
    ->ArgsProduct({{2, 3, 4}, {0, 1}, {1}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK_CAPTURE(runScene, cliff, std::string("cliff"))
    ->Name("Scene/cliff")
    ->ArgsProduct({{2, 3, 4}, {0, 1}, {1}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
// Rocks on a real DEM (the Tyrol slope's 5 m cells, glacial-deposit ground, 20 rocks, 40 s).
BENCHMARK_CAPTURE(runSceneFile, rockfall, std::string("rockfall"))
    ->Name("SceneFile/rockfall")
    ->Args({1})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
// Threads: the checksum must equal the one-thread row's.
BENCHMARK_CAPTURE(runScene, crosses2, std::string("crosses"))
    ->Name("Scene/crosses")
    ->Args({4, 1, 2})
    ->Args({4, 0, 2})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK_CAPTURE(runScene, crosses6, std::string("crosses"))
    ->Name("Scene/crosses")
    ->Args({6, 1, 1})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
// The crosses with the extensions and the clearance step (the goal of Lv 6 crosses in the Lv 4
// time names no step rule).
BENCHMARK_CAPTURE(runScene, crossesClearance, std::string("crosses"), true)
    ->Name("SceneClearance/crosses")
    ->Args({4, 1, 1})
    ->Args({6, 1, 1})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK_CAPTURE(rockfall, eq20, false, false)
    ->Name("Rockfall")
    ->Args({100, 1})
    ->Args({100, 2})
    ->Args({300, 1})
    ->Args({300, 2})
    ->Args({1000, 1})
    ->Args({1000, 2})
    ->Args({3000, 1})
    ->Args({3000, 2})
    ->Args({10000, 1})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->Iterations(1);
BENCHMARK_CAPTURE(rockfall, clearance, true, false)
    ->Name("RockfallClearance")
    ->Args({100, 1})
    ->Args({300, 1})
    ->Args({1000, 1})
    ->Args({1000, 2})
    ->Args({3000, 2})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->Iterations(1);
BENCHMARK_CAPTURE(rockfall, wide, false, true)
    ->Name("RockfallWide")
    ->Args({100, 2})
    ->Args({300, 2})
    ->Args({1000, 2})
    ->Args({3000, 2})
    ->Args({10000, 2})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->Iterations(1);
BENCHMARK(treeBuild)->Name("TreeBuild")->Arg(6)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(treeBuild1M)
    ->Name("TreeBuild1M")
    ->Arg(7)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->Iterations(1);

BENCHMARK(diagnosticsBuild1M)
    ->Name("DiagnosticsBuild1M")
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->Iterations(1);

BENCHMARK_CAPTURE(loadDem, tirol_geotiff,
                  std::string(VOXFALL_SOURCE_DIR) + "/scenes/terrain/tirol_avagar_dem.tif")
    ->Unit(benchmark::kMillisecond);

int main(int argc, char** argv) {
  // The ASCII original is not in the repository (the GeoTIFF is a third of its size).
  if (const char* ascii = std::getenv("VOXFALL_BENCH_ASCII_DEM"))
    benchmark::RegisterBenchmark("loadDem/ascii", loadDem, std::string(ascii))
        ->Unit(benchmark::kMillisecond);
  benchmark::Initialize(&argc, argv);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
}

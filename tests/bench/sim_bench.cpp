// voxfall's simulation benchmark (Google Benchmark). Build and run:
//   cmake --build build --target sim_bench && build/tests/bench/sim_bench
// Rows:
//   Scene/<name>/<level>: a whole run of scenes/<name>.toml (the same scene files the CLI and
//     the tests use) at voxel level Lv (every shape) with the eq.-20 step. Counters: wall seconds
//     per simulated second (sec_per_sim_s), steps, sphere tests, contacts; the label carries the
//     trajectory checksum, so every benchmark run is also a determinism check.
//   LoadDem/<file>: loading a DEM through GDAL: the 520 x 387 Tyrol grid as the repository's
//     Float64 GeoTIFF, and as an ESRI ASCII grid (VOXFALL_BENCH_ASCII_DEM, if set, names one,
//     e.g. the AvaFrame original).
//   TreeBuild/<level>: voxel sphere tree of a 100k-triangle closed mesh (a bumpy sphere).
#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdlib>
#include <string>

#include "sim/recorder.h"
#include "sim/scene/scene.h"
#include "sim/shape/heightfield.h"
#include "sim/shape/sphere_tree.h"

namespace {

std::string scenePath(const std::string& name) {
  return std::string(VOXFALL_SOURCE_DIR) + "/scenes/" + name + ".toml";
}

void runScene(benchmark::State& state, const std::string& name) {
  vf::SceneSpec spec = vf::loadScene(scenePath(name));
  spec.level = static_cast<int>(state.range(0));
  for (vf::ShapeSpec& shape : spec.shapes) shape.level.reset();  // as `--level` does
  vf::RunSummary summary;
  for (auto _ : state) {
    state.PauseTiming();
    vf::BuiltScene built = vf::buildScene(spec);  // shape building is not the step's cost
    state.ResumeTiming();
    vf::Recorder recorder(*built.world, spec.fps, spec.duration);
    for (int k = 0; k < recorder.frameCount(); ++k) recorder.advanceToFrame(k);
    summary = recorder.summary();
  }
  state.counters["sec_per_sim_s"] = benchmark::Counter(
      spec.duration, benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
  state.counters["steps"] = static_cast<double>(summary.totals.steps);
  state.counters["sphere_tests"] = static_cast<double>(summary.totals.sphereTests);
  state.counters["contacts"] = static_cast<double>(summary.totals.contacts);
  state.SetLabel("checksum " + summary.checksumHex());
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

void treeBuild(benchmark::State& state) {
  const vf::TriMesh mesh = bumpySphere(200, 251);  // 2 * 251 * 199 = 99,898 triangles
  std::size_t leaves = 0;
  for (auto _ : state) {
    const vf::SphereTree tree = vf::buildSphereTree(mesh, static_cast<int>(state.range(0)));
    leaves = tree.leaves().centers.size();
    benchmark::DoNotOptimize(leaves);
  }
  state.counters["triangles"] = static_cast<double>(mesh.triangles.size());
  state.counters["leaf_spheres"] = static_cast<double>(leaves);
}

}  // namespace

BENCHMARK_CAPTURE(runScene, cubes, std::string("cubes"))
    ->Name("Scene/cubes")
    ->DenseRange(2, 4)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK_CAPTURE(runScene, blocks, std::string("blocks"))
    ->Name("Scene/blocks")
    ->DenseRange(2, 4)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK_CAPTURE(runScene, highpoly, std::string("highpoly"))
    ->Name("Scene/highpoly")
    ->DenseRange(2, 4)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK_CAPTURE(runScene, stack, std::string("stack"))
    ->Name("Scene/stack")
    ->DenseRange(2, 4)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK_CAPTURE(runScene, crosses, std::string("crosses"))
    ->Name("Scene/crosses")
    ->DenseRange(2, 4)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK_CAPTURE(runScene, barrel, std::string("barrel"))
    ->Name("Scene/barrel")
    ->DenseRange(2, 4)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK_CAPTURE(runScene, cliff, std::string("cliff"))
    ->Name("Scene/cliff")
    ->DenseRange(2, 4)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK(treeBuild)->Name("TreeBuild")->Arg(6)->Unit(benchmark::kMillisecond)->UseRealTime();

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

// Ensemble throughput (README, "Ensembles and hazard maps"): realisations per second of the
// Tyrol ensemble (scenes/rockfall_ensemble.toml) on 1 and 2 threads, the same 8 realisations
// each time, and a hash of their checksums (the same for every thread count: a determinism
// check in every benchmark run). Run: build/tests/bench/ensemble_bench
#include <benchmark/benchmark.h>

#include <cstdint>
#include <numeric>
#include <string>
#include <vector>

#include "sim/ensemble/ensemble.h"
#include "sim/scene/scene.h"

namespace {

void tyrolEnsemble(benchmark::State& state) {
  const vf::SceneSpec spec =
      vf::loadScene(std::string(VOXFALL_SOURCE_DIR) + "/scenes/rockfall_ensemble.toml");
  const vf::Ensemble ensemble(spec);  // terrain and shapes once, outside the timing
  std::vector<std::int64_t> indices(8);
  std::iota(indices.begin(), indices.end(), 0);
  std::uint64_t hash = 0;
  for (auto _ : state) {
    const auto results = vf::runRealisations(ensemble, indices, spec.ensemble->seed,
                                             static_cast<int>(state.range(0)), false, {}, {});
    hash = 0;
    for (const auto& r : results) hash = hash * 1099511628211ull ^ r.checksum;
    benchmark::DoNotOptimize(hash);
  }
  state.counters["realisations/s"] = benchmark::Counter(
      static_cast<double>(indices.size()) * static_cast<double>(state.iterations()),
      benchmark::Counter::kIsRate);
  state.counters["checksums"] = static_cast<double>(hash % 1000000);
}
BENCHMARK(tyrolEnsemble)
    ->Name("TyrolEnsemble8")
    ->Arg(1)
    ->Arg(2)
    ->Unit(benchmark::kSecond)
    ->UseRealTime()
    ->Iterations(1)
    ->Repetitions(3)
    ->ReportAggregatesOnly(true);

}  // namespace

BENCHMARK_MAIN();

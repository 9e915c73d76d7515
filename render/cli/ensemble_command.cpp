// voxfall ensemble SCENE --runs N: options into an EnsembleRequest; the run (journal,
// realisations, MPI ranks, outputs, stop policy) is render/run/ensemble_run.h.
#include <CLI/CLI.hpp>
#include <cstdint>
#include <limits>
#include <memory>

#include "render/cli/commands.h"
#include "render/cli/options.h"
#include "render/run/ensemble_run.h"
#include "sim/ensemble/ensemble_shards.h"

namespace vf::cli {

void addEnsembleCommand(CLI::App& app, int& exitCode) {
  auto o = std::make_shared<EnsembleRequest>();
  CLI::App* sub = app.add_subcommand(
      "ensemble",
      "Run many independent realisations of a scene's [ensemble] release and write per-cell "
      "hazard rasters (GeoTIFF and ESRI ASCII), runs.csv and summary.json");
  sub->add_option("SCENE", o->scene, "scene file (TOML) with an [ensemble] table")
      ->required()
      ->type_name("");
  sub->add_option("--runs", o->runs, "number of realisations N")
      ->required()
      ->type_name("N")
      ->check(CLI::Range(std::int64_t{1}, std::int64_t{100000000}));
  sub->add_option("--seed", o->seed,
                  "ensemble seed S (default: [ensemble] seed); realisation i uses a seed made "
                  "from S and i only")
      ->type_name("S")
      ->check(integerIn(0, std::numeric_limits<std::uint64_t>::max()));
  sub->add_option("--jobs,-j", o->jobs,
                  "threads running realisations (outputs are the same bytes for any value)")
      ->type_name("J")
      ->check(CLI::Range(1, 1024));
  CLI::Option* only =
      sub->add_option("--only", o->only,
                      "run realisation i of the N alone (the same trajectory as inside the "
                      "ensemble; no journal)")
          ->type_name("i");
  sub->add_option("-o,--output", o->files.outDir, "output folder (default out/SCENE_ensemble)")
      ->type_name("DIR");
  sub->add_flag("--resume", o->resume,
                "continue the ensemble whose journal is in the output folder (the same scene, "
                "seed and options): run only the realisations it lacks, up to --runs")
      ->excludes(only);
  sub->add_option("--shard", o->shard,
                  "run shard i of n (realisations i, i + n, i + 2n, ...) into a journal only; "
                  "combine the shards with `voxfall ensemble-merge`")
      ->type_name("i/n")
      ->excludes(only)
      ->check([](const std::string& text) { return shardProblem(text); });
  sub->add_flag("--converge", o->files.converge,
                "write converge.csv and print how reach probability and p95 energy at the 3 "
                "busiest cells change over N/8, N/4, N/2, N realisations");
  sub->add_flag("--paths", o->files.paths,
                "write paths.csv: every realisation's centre of mass after every step");
  sub->add_option("--video-runs", o->files.videoRuns,
                  "write the first K realisations' trajectories as ensemble_subset.bake and render "
                  "it to trajectories.mp4 (the scene's [output] and [camera])")
      ->type_name("K")
      ->check(CLI::Range(1, 10000));
  sub->add_flag("--maps", o->files.maps,
                "also draw a hazard map PNG per statistic (over a hillshade of the DEM, with the "
                "release areas) and runout.png (runout and reach-angle distributions)");
  addMapExtentOption(*sub, o->files.extent);
  addPhysicsOptions(*sub, o->overrides);
  sub->add_flag("--quiet,-q", o->files.quiet, "no progress line on stderr");
  addOverwriteFlags(*sub, o->files.overwrite, o->files.neverOverwrite);
  sub->callback([o, &exitCode] { exitCode = vf::exitCode(runEnsemble(*o)); });
}

}  // namespace vf::cli

// voxfall ensemble-merge DIR... -o OUT: options into a MergeRequest; the merge is
// render/run/ensemble_merge_run.h.
#include <CLI/CLI.hpp>
#include <memory>

#include "render/cli/commands.h"
#include "render/cli/options.h"
#include "render/run/ensemble_merge_run.h"

namespace vf::cli {

void addEnsembleMergeCommand(CLI::App& app, int& exitCode) {
  auto o = std::make_shared<MergeRequest>();
  CLI::App* sub = app.add_subcommand(
      "ensemble-merge",
      "Combine the journals of an ensemble's shards (ensemble --shard i/n) into the outputs "
      "one run of the whole ensemble writes, byte for byte");
  sub->add_option("DIR", o->parts,
                  "output folders of the shards (or their ensemble.journal files), together "
                  "holding realisations 0 .. N-1 once each")
      ->required()
      ->type_name("");
  sub->add_option("-o,--output", o->files.outDir, "output folder of the merged ensemble")
      ->required()
      ->type_name("OUT");
  sub->add_flag("--converge", o->files.converge, "also write converge.csv (as ensemble does)");
  sub->add_flag("--maps", o->files.maps,
                "also draw a hazard map PNG per statistic and runout.png (as ensemble does)");
  addMapExtentOption(*sub, o->files.extent);
  sub->add_option("--video-runs", o->files.videoRuns,
                  "also write the first K realisations as ensemble_subset.bake and render it to "
                  "trajectories.mp4 (as ensemble does)")
      ->type_name("K")
      ->check(CLI::Range(1, 10000));
  sub->add_flag("--quiet,-q", o->files.quiet, "no progress line on stderr");
  addOverwriteFlags(*sub, o->files.overwrite, o->files.neverOverwrite);
  sub->callback([o, &exitCode] { exitCode = vf::exitCode(runEnsembleMerge(*o)); });
}

}  // namespace vf::cli

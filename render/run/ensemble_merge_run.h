// An ensemble merge as a library call: what `voxfall ensemble-merge DIR... -o OUT` does. The
// journals of an ensemble's shards (`voxfall ensemble --shard i/n`), or of any runs that
// together hold realisations 0 .. N-1 once each, combined into the outputs one run of the whole
// ensemble writes, byte for byte (docs/ensembles.md, "Long runs"). The checks (same ensemble, no
// overlap, nothing missing) are sim/ensemble/ensemble_shards.h's; the outputs are
// render/run/ensemble_files.h's, as for `voxfall ensemble`. OUT also gets the merged journal, so
// the ensemble can be extended with `voxfall ensemble ... --resume -o OUT`.
#pragma once

#include <string>
#include <vector>

#include "render/run/ensemble_files.h"
#include "render/run/stop_policy.h"

namespace vf {

struct MergeRequest {
  std::vector<std::string> parts;  // output folders of the shards (or journal files)
  EnsembleFileOptions files;       // the merged ensemble's folder and what goes in it
};

// Checks and merges the journals and writes the outputs. Bad input throws InputError.
RunStatus runEnsembleMerge(const MergeRequest& request);

}  // namespace vf

// Which realisations a run of an ensemble runs and reduces, when it continues a journal, runs a
// shard of the ensemble, or merges the journals of several shards (docs/ensembles.md, "Long
// runs"). Realisation i is the same whoever runs it (its seed depends on the ensemble seed and i
// alone), so any split of 0 .. N-1 reduces, in index order, to the bytes of one run.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "sim/ensemble/ensemble.h"
#include "sim/ensemble/ensemble_journal.h"

namespace vf {

// Shard i of n: realisations i, i + n, i + 2n, ... (0 <= i < n).
struct Shard {
  int index = 0;
  int count = 1;
};

// "i/n" as a Shard; InputError naming --shard when it is not two integers 0 <= i < n <= 100000.
Shard parseShard(const std::string& text);
// What is wrong with `text` as a shard, or "" when it is one.
std::string shardProblem(const std::string& text);
// "i/n", or "" for none.
std::string shardText(const std::optional<Shard>& shard);

// The realisations of `runs` (those of `shard` when given) not among `done`, in index order.
std::vector<std::int64_t> indicesToRun(std::int64_t runs, const std::optional<Shard>& shard,
                                       std::vector<std::int64_t> done);
// The indices of `results`, in their order.
std::vector<std::int64_t> indicesOf(const std::vector<RealisationResult>& results);

// The results with an index below `runs`, one per index, in index order: what the outputs are
// made of.
std::vector<RealisationResult> resultsInIndexOrder(std::vector<RealisationResult> results,
                                                   std::int64_t runs);

// The indices of `results` (in index order) as ranges: "0-5,7,9-12".
std::string indexRanges(const std::vector<RealisationResult>& results);

// One journal to merge, and the name to call it by in messages (its folder).
struct JournalPart {
  std::string name;
  JournalContents journal;
};

// The realisations 0 .. N-1 of the journals, in index order, N being their --runs. InputError
// when the journals are of different runs (naming the first difference), when one realisation
// is in two of them, or when one is in none.
std::vector<RealisationResult> mergeJournals(std::vector<JournalPart>& parts);

}  // namespace vf

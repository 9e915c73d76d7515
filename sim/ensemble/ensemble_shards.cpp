// Realisations to run, reduce and merge (see ensemble_shards.h).
#include "sim/ensemble/ensemble_shards.h"

#include <algorithm>
#include <map>

#include "sim/core/error.h"

namespace vf {

Shard parseShard(const std::string& text) {
  const std::size_t slash = text.find('/');
  const auto number = [](const std::string& s) {
    if (s.empty() || s.size() > 6 || s.find_first_not_of("0123456789") != std::string::npos)
      return -1;
    return std::stoi(s);
  };
  Shard s;
  if (slash != std::string::npos) {
    s.index = number(text.substr(0, slash));
    s.count = number(text.substr(slash + 1));
  }
  if (slash == std::string::npos || s.index < 0 || s.count < 1 || s.count > 100000 ||
      s.index >= s.count)
    throw InputError("--shard",
                     "must be i/n with 0 <= i < n <= 100000 (shard i of n), got '" + text + "'");
  return s;
}

std::string shardProblem(const std::string& text) {
  try {
    parseShard(text);
    return "";
  } catch (const InputError& e) {
    return e.message();
  }
}

std::string shardText(const std::optional<Shard>& shard) {
  if (!shard) return "";
  return std::to_string(shard->index) + "/" + std::to_string(shard->count);
}

std::vector<std::int64_t> indicesOf(const std::vector<RealisationResult>& results) {
  std::vector<std::int64_t> out;
  for (const RealisationResult& r : results) out.push_back(r.index);
  return out;
}

std::vector<std::int64_t> indicesToRun(std::int64_t runs, const std::optional<Shard>& shard,
                                       std::vector<std::int64_t> have) {
  std::sort(have.begin(), have.end());
  const std::int64_t first = shard ? shard->index : 0, step = shard ? shard->count : 1;
  std::vector<std::int64_t> out;
  for (std::int64_t i = first; i < runs; i += step)
    if (!std::binary_search(have.begin(), have.end(), i)) out.push_back(i);
  return out;
}

std::vector<RealisationResult> resultsInIndexOrder(std::vector<RealisationResult> results,
                                                   std::int64_t runs) {
  std::stable_sort(
      results.begin(), results.end(),
      [](const RealisationResult& a, const RealisationResult& b) { return a.index < b.index; });
  std::vector<RealisationResult> out;
  for (RealisationResult& r : results)
    if (r.index < runs && (out.empty() || out.back().index != r.index)) out.push_back(std::move(r));
  return out;
}

std::string indexRanges(const std::vector<RealisationResult>& results) {
  std::string s;
  for (std::size_t k = 0; k < results.size();) {
    std::size_t last = k;
    while (last + 1 < results.size() && results[last + 1].index == results[last].index + 1) ++last;
    if (!s.empty()) s += ',';
    s += std::to_string(results[k].index);
    if (last > k) s.append("-").append(std::to_string(results[last].index));
    k = last + 1;
  }
  return s;
}

namespace {

// Every part is of the same run as the first: header (the shard aside) and --runs.
void checkSameRun(const std::vector<JournalPart>& parts) {
  const JournalPart& first = parts.front();
  for (const JournalPart& p : parts) {
    const std::string d = journalDifference(first.journal.header, p.journal.header, false);
    if (!d.empty())
      throw InputError(p.name, "is not a shard of the same ensemble as " + first.name + ": " + d);
    if (p.journal.runsRequested != first.journal.runsRequested)
      throw InputError(p.name, "is a shard of --runs " + std::to_string(p.journal.runsRequested) +
                                   ", " + first.name + " of --runs " +
                                   std::to_string(first.journal.runsRequested));
  }
}

// "3, 5 and 9 (3 in all)": the first few of `missing` (`total` in all).
std::string listed(const std::vector<std::int64_t>& first, std::int64_t total) {
  std::string s;
  const std::size_t shown = first.size();
  for (std::size_t k = 0; k < shown; ++k)
    s += (k == 0                                                        ? ""
          : k + 1 == shown && static_cast<std::int64_t>(shown) == total ? " and "
                                                                        : ", ") +
         std::to_string(first[k]);
  if (static_cast<std::int64_t>(shown) < total) s += ", ...";
  return s + " (" + std::to_string(total) + " in all)";
}

}  // namespace

std::vector<RealisationResult> mergeJournals(std::vector<JournalPart>& parts) {
  if (parts.empty()) throw InputError("", "no journals to merge");
  checkSameRun(parts);
  const std::int64_t runs = parts.front().journal.runsRequested;
  std::map<std::int64_t, std::size_t> owner;  // realisation -> part
  std::vector<RealisationResult> all;
  for (std::size_t k = 0; k < parts.size(); ++k) {
    for (RealisationResult& r : resultsInIndexOrder(std::move(parts[k].journal.results), runs)) {
      const auto [at, fresh] = owner.emplace(r.index, k);
      if (!fresh)
        throw InputError(parts[k].name, "holds realisation " + std::to_string(r.index) +
                                            ", which " + parts[at->second].name +
                                            " holds too: the shards overlap");
      all.push_back(std::move(r));
    }
  }
  std::vector<std::int64_t> missing;
  const std::int64_t total = runs - static_cast<std::int64_t>(owner.size());
  for (std::int64_t i = 0; i < runs && missing.size() < 5 && total > 0; ++i)
    if (!owner.count(i)) missing.push_back(i);
  if (total > 0)
    throw InputError("", "realisations " + listed(missing, total) + " of --runs " +
                             std::to_string(runs) +
                             " are in none of the journals: run (or --resume) the shards that "
                             "hold them, then merge again");
  return resultsInIndexOrder(std::move(all), runs);
}

}  // namespace vf

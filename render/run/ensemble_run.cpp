#include "render/run/ensemble_run.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "render/output/output_file.h"
#include "render/progress.h"
#include "render/run/ensemble_mpi.h"
#include "render/run/run_input.h"
#include "render/run/run_report.h"
#include "sim/core/error.h"
#include "sim/ensemble/ensemble.h"
#include "sim/ensemble/ensemble_journal.h"
#include "sim/ensemble/ensemble_shards.h"
#include "sim/scene/scene.h"

namespace vf {
namespace {

namespace fs = std::filesystem;

// What rank 0 holds while the realisations run: the journal and the outputs to write.
struct RootState {
  std::string journalPath;
  std::optional<JournalWriter> journal;
  std::vector<std::int64_t> done;  // realisations already in the journal (--resume)
  std::optional<EnsembleFiles> files;
};

std::string defaultFolder(const SceneSpec& spec, const std::optional<Shard>& shard) {
  if (!shard) return "out/" + spec.name + "_ensemble";
  return "out/" + spec.name + "_ensemble_shard-" + std::to_string(shard->index) + "-of-" +
         std::to_string(shard->count);
}

// The journal continued (--resume: the same scene, version and options, else an error naming
// the difference) or started (refused where one exists, unless -y).
void openJournal(RootState& root, const EnsembleRequest& o, const JournalHeader& header) {
  const bool exists = fs::exists(root.journalPath);
  if (o.resume) {
    if (!exists)
      throw InputError(root.journalPath,
                       "no journal to resume in this folder; run without --resume to start");
    const JournalContents j = readJournal(root.journalPath);
    const std::string d = journalDifference(j.header, header, true);
    if (!d.empty())
      throw InputError(root.journalPath, "cannot resume: " + d +
                                             "; resume with the journal's scene and options, or "
                                             "start over in another folder");
    if (j.tornBytes > 0)
      std::fprintf(stderr, "voxfall: %s: dropped a record cut short (%llu bytes) at its end\n",
                   root.journalPath.c_str(), static_cast<unsigned long long>(j.tornBytes));
    root.done = indicesOf(j.results);
    root.journal.emplace(root.journalPath, j.goodBytes);
  } else {
    if (exists && o.files.neverOverwrite)
      throw InputError(root.journalPath, "already exists; not overwritten (-n)");
    if (exists && !o.files.overwrite)
      throw InputError(root.journalPath,
                       "already exists: an ensemble ran into this folder; continue it with "
                       "--resume, start it over with -y, or choose another -o");
    root.journal.emplace(root.journalPath, header);
  }
}

// Checks and opens, on rank 0, everything the run writes: the journal and the outputs (a shard
// writes its journal only; --only writes no journal).
void openRoot(RootState& root, const EnsembleRequest& o, const SceneSpec& spec, const Ensemble& ens,
              std::uint64_t seed, const std::optional<Shard>& shard) {
  if (!o.files.extent.empty()) mapExtent(o.files.extent, ens.dem());  // before any file
  OutputRules rules = runOutputRules(spec, o.scene, o.files.overwrite, o.files.neverOverwrite);
  for (const ReleaseSpec& r : spec.ensemble->releases)
    if (!r.path.empty()) rules.inputs.push_back(r.path);
  if (!spec.groundClassesPath.empty()) rules.inputs.push_back(spec.groundClassesPath);
  if (!o.only) {
    std::error_code ec;
    fs::create_directories(o.files.outDir, ec);
    removeStalePartials(o.files.outDir);
    root.journalPath = (fs::path(o.files.outDir) / kJournalName).string();
    checkOutputPath(root.journalPath, OutputRules{Overwrite::always, rules.inputs});
    openJournal(root, o,
                makeJournalHeader(spec, o.scene, voxfallVersion(), seed, o.overrides, o.files.paths,
                                  shardText(shard)));
    root.journal->addRuns(o.runs);
  }
  // A resumed run replaces the outputs its journal's run wrote: they are made from the journal.
  if (o.resume) rules.overwrite = Overwrite::always;
  if (!shard) root.files.emplace(o.files, rules, ens.dem());
}

// The realisations this process runs: rank r takes every size-th of those still to run (round
// robin balances the ranks when realisation costs drift with the index, cheaply).
std::vector<std::int64_t> myIndices(const EnsembleRequest& o, MpiSession& mpi,
                                    const std::optional<Shard>& shard,
                                    std::vector<std::int64_t> done) {
  if (o.only)
    return mpi.rank() == 0 ? std::vector<std::int64_t>{*o.only} : std::vector<std::int64_t>{};
  std::string bytes(reinterpret_cast<const char*>(done.data()), done.size() * sizeof(std::int64_t));
  mpi.broadcast(bytes);
  done.resize(bytes.size() / sizeof(std::int64_t));
  std::memcpy(done.data(), bytes.data(), bytes.size());
  const std::vector<std::int64_t> todo = indicesToRun(o.runs, shard, std::move(done));
  std::vector<std::int64_t> mine;
  for (std::size_t k = static_cast<std::size_t>(mpi.rank()); k < todo.size();
       k += static_cast<std::size_t>(mpi.size()))
    mine.push_back(todo[k]);
  return mine;
}

// Runs this process's realisations. Each complete one goes to the journal as it completes:
// rank 0 appends its own and those the other ranks send; they send theirs to rank 0.
std::vector<RealisationResult> runMine(const EnsembleRequest& o, const Ensemble& ens,
                                       std::uint64_t seed, const std::vector<std::int64_t>& indices,
                                       MpiSession& mpi, RootState& root) {
  const bool isRoot = mpi.rank() == 0;
  const auto journal = [&](const RealisationResult& r) {
    if (root.journal) root.journal->add(r);
  };
  const auto receive = [&](const std::string& bytes) {
    std::size_t at = 0;
    journal(deserializeResult(bytes, at));
  };
  const auto onResult = [&](const RealisationResult& r) {
    if (isRoot) return journal(r);
    std::string bytes;
    serializeResult(r, bytes);
    mpi.send(bytes);
  };
  const auto started = std::chrono::steady_clock::now();
  Progress progress(ens.spec().name + " ensemble", static_cast<int>(indices.size()),
                    isRoot && !o.files.quiet);
  const auto report = [&](int done) {
    mpi.receive(false, receive);
    const double s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
    char detail[96];
    std::snprintf(detail, sizeof detail, "%.2f realisations/s%s", s > 0 ? done / s : 0.0,
                  mpi.size() > 1 ? " on rank 0" : "");
    progress.update(done, detail);
  };
  std::exception_ptr failure;
  std::vector<RealisationResult> mine;
  try {
    mine = runRealisations(
        ens, indices, seed, std::max(1, o.jobs), o.files.paths, report,
        [] { return stopRequested() != 0; }, onResult);
  } catch (...) {
    failure = std::current_exception();
  }
  progress.finish();
  if (isRoot)
    mpi.receive(true, receive);
  else
    mpi.sendDone();
  if (!mpi.allOk(!failure)) {
    if (failure) std::rethrow_exception(failure);
    throw InputError("", "another MPI rank failed (it said why)");
  }
  return mine;
}

// What the outputs are made of: the journal's realisations in index order (the --only one
// from memory).
std::vector<RealisationResult> completeRealisations(const EnsembleRequest& o, RootState& root,
                                                    std::vector<RealisationResult> mine) {
  if (o.only) {
    std::erase_if(mine, [](const RealisationResult& r) { return !r.complete; });
    return mine;
  }
  root.journal.reset();  // flushed and closed
  return resultsInIndexOrder(readJournal(root.journalPath).results, o.runs);
}

RunStatus finishShard(const EnsembleRequest& o, const SceneSpec& spec, const Shard& shard,
                      const std::vector<RealisationResult>& all, int stop) {
  const std::int64_t share = static_cast<std::int64_t>(indicesToRun(o.runs, shard, {}).size());
  std::int64_t have = 0;
  for (const RealisationResult& r : all)
    if (r.index % shard.count == shard.index) ++have;
  std::printf("%s: shard %s of --runs %lld: %lld of its %lld realisations in %s\n",
              spec.name.c_str(), shardText(shard).c_str(), static_cast<long long>(o.runs),
              static_cast<long long>(have), static_cast<long long>(share),
              (fs::path(o.files.outDir) / kJournalName).c_str());
  if (stop)
    std::fprintf(stderr,
                 "voxfall: interrupted; the journal keeps the complete realisations: "
                 "continue the shard with --resume\n");
  return stop ? RunStatus::stopped(stop) : RunStatus::done();
}

// How many realisations this run ran, how fast, and how many it took from the journal.
void reportTimes(const EnsembleRequest& o, const RootState& root,
                 const std::vector<RealisationResult>& all, double seconds, int ranks) {
  std::vector<std::int64_t> done = root.done;
  std::sort(done.begin(), done.end());
  std::size_t taken = 0;
  for (const RealisationResult& r : all)
    taken += std::binary_search(done.begin(), done.end(), r.index);
  const std::size_t ran = all.size() - taken;
  const int jobs = std::max(1, o.jobs);
  const std::string tail = taken ? ", " + std::to_string(taken) + " taken from the journal" : "";
  std::fprintf(stderr,
               "voxfall: %zu realisations run in %.2f s (%.2f realisations/s, %d thread%s%s)%s\n",
               ran, seconds, seconds > 0 ? ran / seconds : 0.0, jobs, jobs == 1 ? "" : "s",
               ranks > 1 ? (" x " + std::to_string(ranks) + " ranks").c_str() : "", tail.c_str());
}

// Writes the outputs of `all` and says what was written.
RunStatus finishEnsemble(const EnsembleRequest& o, const Ensemble& ens, RootState& root,
                         const std::vector<RealisationResult>& all, std::uint64_t seed, int stop,
                         double seconds, int ranks) {
  if (all.empty()) {
    std::fprintf(stderr, "voxfall: %s; no realisation complete, no output written\n",
                 stop ? "interrupted" : "nothing ran");
    return stop ? RunStatus::stopped(stop) : RunStatus::failed();
  }
  const std::int64_t requested = o.only ? 1 : o.runs;
  EnsembleRunInfo info{seed, requested, o.only, 0};
  // Interrupted means said: the summary records it when the files miss realisations.
  if (stop && static_cast<std::int64_t>(all.size()) < requested) info.stopSignal = stop;
  const RunStatus video = root.files->write(ens, info, all);
  reportEnsemble(ens, info, all, *root.files);
  reportTimes(o, root, all, seconds, ranks);
  if (stop) {
    std::fprintf(stderr,
                 "voxfall: interrupted; the files hold the %zu complete realisations (%s) of "
                 "%lld; continue with --resume\n",
                 all.size(), indexRanges(all).c_str(), static_cast<long long>(requested));
    return RunStatus::stopped(stop);
  }
  return video;
}

}  // namespace

RunStatus runEnsemble(const EnsembleRequest& given) {
  EnsembleRequest o = given;
  SceneSpec spec = loadScene(o.scene);
  applyOverrides(spec, o.overrides);
  if (!spec.ensemble)
    throw InputError(spec.path,
                     "the scene has no [ensemble] table (what varies between realisations; see "
                     "docs/ensembles.md)");
  if (o.only && (*o.only < 0 || *o.only >= o.runs))
    throw InputError("", "--only " + std::to_string(*o.only) + " is not a realisation of --runs " +
                             std::to_string(o.runs) + " (0 .. " + std::to_string(o.runs - 1) + ")");
  const std::optional<Shard> shard =
      o.shard.empty() ? std::nullopt : std::optional<Shard>(parseShard(o.shard));
  const std::uint64_t seed = o.seed.value_or(spec.ensemble->seed);
  if (o.files.outDir.empty()) o.files.outDir = defaultFolder(spec, shard);
  o.files.lines = !spec.evaluationLines.empty();
  o.files.barriers = !spec.barriers.empty();
  o.files.heightClasses = spec.ensemble->heightClasses;

  MpiSession mpi;
  // Rank 0 checks and opens the journal and outputs before any realisation runs; every rank
  // learns whether that worked, so none waits for a rank that gave up.
  std::optional<Ensemble> ensemble;
  RootState root;
  std::exception_ptr failure;
  try {
    ensemble.emplace(spec);  // terrain and shapes, once (a few seconds at most)
    if (mpi.rank() == 0) openRoot(root, o, spec, *ensemble, seed, shard);
  } catch (...) {
    failure = std::current_exception();
  }
  if (!mpi.allOk(!failure)) {
    if (failure) std::rethrow_exception(failure);
    return RunStatus::failed();  // another rank reported the problem
  }
  watchForStop();
  const std::vector<std::int64_t> indices = myIndices(o, mpi, shard, root.done);
  const auto started = std::chrono::steady_clock::now();
  std::vector<RealisationResult> mine = runMine(o, *ensemble, seed, indices, mpi, root);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  const int stop = stopRequested();
  if (mpi.rank() != 0) return stop ? RunStatus::stopped(stop) : RunStatus::done();
  const std::vector<RealisationResult> all = completeRealisations(o, root, std::move(mine));
  if (shard) return finishShard(o, spec, *shard, all, stop);
  return finishEnsemble(o, *ensemble, root, all, seed, stop, seconds, mpi.size());
}

}  // namespace vf

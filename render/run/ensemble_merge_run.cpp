#include "render/run/ensemble_merge_run.h"

#include <filesystem>
#include <string>
#include <vector>

#include "render/run/ensemble_files.h"
#include "render/run/run_input.h"
#include "render/run/run_report.h"
#include "sim/core/error.h"
#include "sim/ensemble/ensemble_journal.h"
#include "sim/ensemble/ensemble_shards.h"

namespace vf {
namespace {

namespace fs = std::filesystem;

// The journal of an output folder, or the file itself.
std::string journalOf(const std::string& part) {
  return fs::is_directory(part) ? (fs::path(part) / kJournalName).string() : part;
}

// The scene file of the journals: as their command line named it when that is the same file
// from here (so that the paths in summary.json are those of one run), else the absolute path.
std::string sceneFileOf(const JournalHeader& header) {
  std::error_code ec;
  return fs::equivalent(header.sceneGiven, header.scenePath, ec) ? header.sceneGiven
                                                                 : header.scenePath;
}

// The scene of the journals, as they ran it; an error naming what changed since.
SceneSpec sceneOf(const JournalHeader& header) {
  SceneSpec spec = loadScene(sceneFileOf(header));
  applyOverrides(spec, header.overrides);
  if (!spec.ensemble) throw InputError(spec.path, "the scene has no [ensemble] table");
  const JournalHeader now = makeJournalHeader(spec, sceneFileOf(header), voxfallVersion(),
                                              header.seed, header.overrides, header.paths, "");
  const std::string d = journalDifference(header, now, false);
  if (!d.empty())
    throw InputError(header.scenePath,
                     "the shards cannot be merged with the scene as it is now: " + d);
  return spec;
}

// OUT's journal: every realisation, in index order, one flush at the end.
void writeMergedJournal(const std::string& path, JournalHeader header, std::int64_t runs,
                        const std::vector<RealisationResult>& all) {
  header.shard.clear();
  JournalWriter journal(path, header);
  journal.syncEachRecord(false);
  journal.addRuns(runs);
  for (const RealisationResult& r : all) journal.add(r);
  journal.flush();
}

}  // namespace

RunStatus runEnsembleMerge(const MergeRequest& o) {
  std::vector<JournalPart> parts;
  std::vector<std::string> journals;
  for (const std::string& p : o.parts) {
    journals.push_back(journalOf(p));
    parts.push_back({p, readJournal(journals.back())});
  }
  const JournalHeader header = parts.front().journal.header;
  const std::int64_t runs = parts.front().journal.runsRequested;
  const std::vector<RealisationResult> all = mergeJournals(parts);
  const SceneSpec spec = sceneOf(header);

  OutputRules rules =
      runOutputRules(spec, header.scenePath, o.files.overwrite, o.files.neverOverwrite);
  for (const ReleaseSpec& r : spec.ensemble->releases)
    if (!r.path.empty()) rules.inputs.push_back(r.path);
  if (!spec.groundClassesPath.empty()) rules.inputs.push_back(spec.groundClassesPath);
  for (const std::string& j : journals) rules.inputs.push_back(j);
  const Ensemble ensemble(spec);
  EnsembleFileOptions files = o.files;
  files.paths = header.paths;
  files.lines = !spec.evaluationLines.empty();
  files.barriers = !spec.barriers.empty();
  files.heightClasses = spec.ensemble->heightClasses;
  EnsembleFiles outputs(files, rules, ensemble.dem());
  const std::string journalPath = (fs::path(o.files.outDir) / kJournalName).string();
  checkOutputPath(journalPath, rules);

  writeMergedJournal(journalPath, header, runs, all);
  const EnsembleRunInfo info{header.seed, runs, std::nullopt, 0};
  const RunStatus status = outputs.write(ensemble, info, all);
  reportEnsemble(ensemble, info, all, outputs);
  return status;
}

}  // namespace vf

// The journal of an ensemble (docs/ensembles.md, "Long runs"; the format is in
// docs/output-formats.md): every complete realisation, appended as it completes and flushed to
// disk, so that a killed run loses only the realisations in flight. The reduced outputs (rasters,
// tables, summary) are made from the journal alone, in index order, so a run that was
// interrupted and resumed, extended, split into shards and merged, or spread over MPI ranks
// writes the same bytes as one uninterrupted run.
//
// Layout: the line "VOXFALL-JOURNAL 1", one line of JSON (the header: what must match for the
// journal to be continued or merged), then records. A record is a 16-byte head (magic, kind,
// payload length), the payload, and a 64-bit checksum of head and payload. Records are only
// ever appended, one write and one fdatasync each; a record cut short by a kill (or a full
// disk) is the last one, is recognised by its length or checksum, and is dropped on reading.
//
// The journal is the one file not written through a temporary name (render/output/
// output_file.h): it is a log that grows while the run goes on, and its records carry their own
// checks instead. Records are in the order the realisations finished, which depends on threads
// and ranks; what is made of them does not.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "sim/ensemble/ensemble.h"
#include "sim/scene/scene.h"

namespace vf {

// A file read by the run, and a hash of its bytes (16 hex digits).
struct JournalInput {
  std::string path;
  std::string hash;
};

// What a journal's run was: everything that changes the realisations' results.
struct JournalHeader {
  std::string version;               // voxfall's version
  std::string sceneName;             // the scene's name
  std::string scenePath;             // the scene file, absolute (ensemble-merge reloads it)
  std::string sceneGiven;            // the scene file as the command line named it
  std::vector<JournalInput> inputs;  // the scene file, then every file it names
  std::uint64_t seed = 0;            // the ensemble seed
  SceneOverrides overrides;          // --level, --step, --collider, --max-steps, ...
  bool paths = false;                // --paths: every step's position is journaled
  std::string shard;                 // "i/n" for a shard, "" for the whole ensemble
};

// The header of a run of `spec` (loaded from `sceneFile`): hashes the scene file and every file
// it names (meshes, terrain, ground classes, source raster). InputError if one cannot be read.
JournalHeader makeJournalHeader(const SceneSpec& spec, const std::string& sceneFile,
                                const std::string& version, std::uint64_t seed,
                                const SceneOverrides& overrides, bool paths,
                                const std::string& shard);

// "" when a run with header `run` may continue the journal with header `journal`; otherwise
// the first difference, as a phrase naming it ("--seed: the journal's run has 7, this one 8").
// The shard is compared only when `compareShard`.
std::string journalDifference(const JournalHeader& journal, const JournalHeader& run,
                              bool compareShard);

// A journal read back.
struct JournalContents {
  JournalHeader header;
  std::int64_t runsRequested = 0;          // --runs of the latest run that wrote to it
  std::vector<RealisationResult> results;  // in the order they were appended
  std::uint64_t goodBytes = 0;             // up to the end of the last whole record
  std::uint64_t tornBytes = 0;             // after it: a record cut short, dropped
};

// Reads a journal. InputError naming the file when it is not a journal, its header is damaged,
// or a record other than the last is damaged.
JournalContents readJournal(const std::string& path);

// Appends records to a journal, each written and flushed to disk before add() returns.
class JournalWriter {
 public:
  // Writes a new journal at `path` with `header` (under a temporary name, renamed when the
  // header is on disk), replacing one that exists.
  JournalWriter(const std::string& path, const JournalHeader& header);
  // Continues the journal at `path` after its first `goodBytes` (a torn record is cut off).
  JournalWriter(const std::string& path, std::uint64_t goodBytes);
  ~JournalWriter();
  JournalWriter(const JournalWriter&) = delete;
  JournalWriter& operator=(const JournalWriter&) = delete;

  // The --runs of the run now writing (the latest one counts).
  void addRuns(std::int64_t runs);
  // One complete realisation.
  void add(const RealisationResult& result);
  // With `each` false, records are flushed by flush() (or the destructor) only: for copying a
  // whole journal at once (ensemble-merge).
  void syncEachRecord(bool each) { syncEach_ = each; }
  void flush();

 private:
  void append(std::uint32_t kind, const std::string& payload);

  std::string path_;
  int fd_ = -1;
  std::uint64_t size_ = 0;
  bool syncEach_ = true;
};

// The file name of the journal inside an ensemble's output folder.
inline constexpr const char* kJournalName = "ensemble.journal";

}  // namespace vf

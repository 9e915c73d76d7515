// How every output of voxfall is written, and how every command stops.
//
// One output-file mechanism: PNG frames, MP4s, CSVs, JSON summaries, bakes, glTF files and
// reports are all written under a temporary name in the destination folder and renamed over
// the real name when complete, so a failed or interrupted run never leaves a half-written file
// in place of a good one. Missing folders are created. Existing outputs follow ffmpeg's
// convention (-y overwrites, -n never does, neither: refused with a message), and a file the
// run reads (scene, mesh, terrain, bake) is never written, whatever the flags.
//
// One stop mechanism: in a run that polls (installStopHandlers(), called through the stop
// policy of render/run/stop_policy.h, which says what a stopped run writes and its exit
// status) the first SIGINT or SIGTERM only raises a flag read between frames (stopSignal()),
// so the run finishes the frame in hand and finalises what it has.
// A second signal, or the first in a command that does not poll, ends the helper programs and
// worker processes running (runHelperProgram, forkWorker), removes every pending temporary file and
// ends the process as the signal would.
#pragma once

#include <sys/types.h>

#include <cstdio>
#include <string>
#include <vector>

namespace vf {

// What to do with an output that already exists (ffmpeg's -y and -n).
enum class Overwrite {
  refuse,  // neither flag: an error that says to use -y
  always,  // -y
  never,   // -n
};

// The rules every output of one run follows.
struct OutputRules {
  Overwrite overwrite = Overwrite::refuse;
  std::vector<std::string> inputs;  // files the run reads: never an output
};

// Rules for outputs that a command replaces by design (reports, `regress --update`).
OutputRules replaceOutputs();

// Throws InputError naming `path` if the rules forbid writing it: it is a folder, it is one of
// the run's inputs, or it exists and may not be overwritten. Checks only; creates nothing.
void checkOutputPath(const std::string& path, const OutputRules& rules);

// An output file written under a temporary name (".NAME.partial-PID-N.EXT" in the destination
// folder, keeping the extension for writers that choose a format by it) and renamed over
// `path` by commit() only. The constructor checks the rules, creates missing folders and the
// temporary file, so an unwritable destination is reported before any simulation starts.
class OutputFile {
 public:
  OutputFile(const std::string& path, const OutputRules& rules);
  ~OutputFile();  // removes the temporary file unless committed
  OutputFile(const OutputFile&) = delete;
  OutputFile& operator=(const OutputFile&) = delete;

  const std::string& path() const { return path_; }
  const std::string& tempPath() const { return tempPath_; }
  // The open temporary file; null after closeStream() or commit().
  std::FILE* stream() { return file_; }
  // Closes the stream for writers that reopen tempPath() by name (e.g. a video muxer).
  void closeStream();
  // Flushes, closes and renames onto path(). Throws InputError on any I/O failure.
  void commit();

 private:
  std::string path_;
  std::string tempPath_;
  std::FILE* file_ = nullptr;
  bool committed_ = false;
};

// Removes the temporary files (".NAME.partial-PID-N.EXT") in `folder` whose process is gone: a
// run killed with SIGKILL (or by a crash, or a power cut) cannot remove its own. A file of a
// process that still runs is kept. OutputFile calls this once per folder and process.
void removeStalePartials(const std::string& folder);

// Runs the program `argv` (argv[0] looked up on the PATH) with stdin from /dev/null and stdout
// and stderr to `logPath`, waits for it and returns its wait status, as std::system would: for
// helper programs that write this run's temporary files (gnuplot). Unlike std::system it leaves
// SIGINT and SIGTERM to this process's handlers meanwhile, and a signal that ends this process
// kills the helper before removing the temporary files, so none is written after.
int runHelperProgram(const std::vector<std::string>& argv, const std::string& logPath);

// fork() for a worker process that runs voxfall's own code and writes its own temporary files
// (regress --jobs): a signal that ends this process first sends it the same signal, whose handler
// removes the worker's temporary files, and waits for it. The parent calls workerEnded(pid) once
// it has waited for the worker itself.
pid_t forkWorker();
void workerEnded(pid_t pid);

// Makes the first SIGINT or SIGTERM a request to stop (see above). A signal the parent made
// the process ignore stays ignored.
void installStopHandlers();
// The first stop signal received (SIGINT or SIGTERM), 0 if none.
int stopSignal();
// "SIGINT", "SIGTERM" (or "signal N"): how summaries name a stop signal.
std::string signalName(int signal);

}  // namespace vf

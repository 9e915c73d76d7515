// How every voxfall run ends, and how it stops on SIGINT or SIGTERM: the one stop policy of every
// command. The runs that poll are simulate, render, export and ensemble.
//
// A run that polls calls watchForStop() once its outputs are checked and opened; from then on
// the first SIGINT or SIGTERM only raises a flag (render/output/output_file.h), which the run
// reads between frames or realisations with stopRequested(). The partial-output rule:
//   - a run stopped with whole frames (or realisations) in hand finalises them (a playable MP4,
//     a CSV up to the last complete frame, a summary that says it was interrupted), says what
//     was written and ends stopped;
//   - a run stopped before its first whole frame writes nothing (the temporary files are
//     removed), says so (stoppedWithNothingWritten) and ends stopped.
// A stopped run's exit status is 128 + the signal (130 for SIGINT, 143 for SIGTERM), what the
// shell reports for a process the signal ended. A second signal, or the first in a command that
// does not poll (filmstrip, diff, regress, figures, plot, ensemble-merge), ends the helper
// programs and worker processes the run started, removes the temporary files and ends the
// process as the signal would (render/output/output_file.h).
#pragma once

#include <string>

namespace vf {

// How a run ended. Bad input is not a status: it is thrown (InputError) with its message.
struct RunStatus {
  enum class End { done, failed, stopped };
  End end = End::done;
  int signal = 0;  // the stop signal when stopped

  static RunStatus done() { return {}; }
  static RunStatus failed() { return {End::failed, 0}; }
  static RunStatus stopped(int signal) { return {End::stopped, signal}; }
  bool isDone() const { return end == End::done; }
  bool isStopped() const { return end == End::stopped; }
};

// From here on the first SIGINT or SIGTERM asks the run to stop instead of ending the process.
void watchForStop();
// The stop signal received (SIGINT or SIGTERM), 0 while none.
int stopRequested();
// The status of a run that stops now: stopped by the signal received, done if none was.
RunStatus stopStatus();
// Prints "voxfall: MESSAGE" to stderr and returns stopStatus(): for a run stopped before it has
// anything whole to write.
RunStatus stoppedWithNothingWritten(
    const std::string& message = "interrupted before the first frame; no output written");

// The process exit status of a run: 0 done, 1 failed, 128 + the signal when stopped.
int exitCode(const RunStatus& status);

}  // namespace vf

#include "render/run/stop_policy.h"

#include <cstdio>

#include "render/output/output_file.h"

namespace vf {

void watchForStop() { installStopHandlers(); }

int stopRequested() { return stopSignal(); }

RunStatus stopStatus() {
  const int signal = stopSignal();
  return signal ? RunStatus::stopped(signal) : RunStatus::done();
}

RunStatus stoppedWithNothingWritten(const std::string& message) {
  std::fprintf(stderr, "voxfall: %s\n", message.c_str());
  return stopStatus();
}

int exitCode(const RunStatus& status) {
  switch (status.end) {
    case RunStatus::End::done:
      return 0;
    case RunStatus::End::failed:
      return 1;
    case RunStatus::End::stopped:
      return 128 + status.signal;  // as the shell reports a process the signal ended
  }
  return 1;
}

}  // namespace vf

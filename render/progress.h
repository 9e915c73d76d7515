// A progress line on stderr for long runs, shared by simulate, render and export.
#pragma once

#include <chrono>
#include <string>

namespace vf {

// One progress line on stderr for runs longer than a second: redrawn in place ("\r") when
// stderr is a terminal, else a plain line every few seconds (logs, CI). Disabled: silent.
class Progress {
 public:
  Progress(std::string label, int totalFrames, bool enabled);
  ~Progress();  // finish()
  // Frames done so far (1..total) and the simulated time reached, s.
  void update(int framesDone, double simTime);
  // Frames done so far (1..total) and what to say about the latest one, e.g. "frame 30,
  // 8.40 frames/s". The line adds the share done, the time elapsed and the time left.
  void update(int framesDone, const std::string& detail);
  // Clears the in-place line, if one was drawn.
  void finish();

 private:
  using Clock = std::chrono::steady_clock;
  std::string label_;
  int total_;
  bool enabled_;
  bool tty_;
  bool drawn_ = false;
  Clock::time_point start_;
  Clock::time_point lastDraw_;
};

}  // namespace vf

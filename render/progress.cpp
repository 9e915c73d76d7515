#include "render/progress.h"

#include <unistd.h>

#include <cstdio>

namespace vf {

namespace {
constexpr double kQuietSeconds = 1.0;  // short runs print nothing
constexpr double kTtyRedraw = 0.1;     // s between in-place redraws
constexpr double kLogInterval = 5.0;   // s between lines when stderr is not a terminal

double seconds(std::chrono::steady_clock::duration d) {
  return std::chrono::duration<double>(d).count();
}
}  // namespace

Progress::Progress(std::string label, int totalFrames, bool enabled)
    : label_(std::move(label)),
      total_(totalFrames),
      enabled_(enabled),
      tty_(::isatty(::fileno(stderr)) != 0),
      start_(Clock::now()),
      lastDraw_(start_) {}

Progress::~Progress() { finish(); }

void Progress::update(int framesDone, double simTime) {
  char detail[48];
  std::snprintf(detail, sizeof detail, "t = %.3f s", simTime);
  update(framesDone, std::string(detail));
}

void Progress::update(int framesDone, const std::string& detail) {
  if (!enabled_) return;
  const auto now = Clock::now();
  const double elapsed = seconds(now - start_);
  if (elapsed < kQuietSeconds) return;
  if (drawn_ && seconds(now - lastDraw_) < (tty_ ? kTtyRedraw : kLogInterval)) return;
  lastDraw_ = now;
  const double fraction = total_ > 0 ? static_cast<double>(framesDone) / total_ : 1.0;
  char eta[32] = "";
  if (fraction > 0 && fraction < 1)
    std::snprintf(eta, sizeof eta, ", about %.0f s left", elapsed * (1 - fraction) / fraction);
  std::fprintf(stderr, "%s%s: %d/%d, %s, %3.0f%%, %.0f s elapsed%s%s", tty_ ? "\r" : "",
               label_.c_str(), framesDone, total_, detail.c_str(), 100 * fraction, elapsed, eta,
               tty_ ? "\033[K" : "\n");
  std::fflush(stderr);
  drawn_ = true;
}

void Progress::finish() {
  if (drawn_ && tty_) {
    std::fputs("\r\033[K", stderr);
    std::fflush(stderr);
  }
  drawn_ = false;
  enabled_ = false;
}

}  // namespace vf

#include "render/cli/run_output.h"

#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cinttypes>
#include <cmath>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <optional>
#include <system_error>

#include "sim/core/error.h"

namespace vf::cli {

namespace fs = std::filesystem;

// --- OutputFile ---------------------------------------------------------------------------

namespace {

// Temporary files not yet committed, for the signal handler. Slots hold pointers to each
// OutputFile's own path string; lock-free atomics are safe to read in a handler, and unlink()
// and raise() are async-signal-safe, so the handler does nothing else.
constexpr int kMaxPending = 16;
std::atomic<const char*> gPending[kMaxPending];
void (*gPreviousInt)(int) = SIG_DFL;
void (*gPreviousTerm)(int) = SIG_DFL;

extern "C" void removePendingAndDie(int sig) {
  for (auto& slot : gPending) {
    if (const char* p = slot.load()) ::unlink(p);
  }
  std::signal(sig, sig == SIGINT ? gPreviousInt : gPreviousTerm);
  std::raise(sig);
}

void registerPending(const char* path) {
  static const bool installed = [] {
    // A signal the parent made us ignore (SIGINT for `cmd &` in a script) stays ignored.
    gPreviousInt = std::signal(SIGINT, removePendingAndDie);
    if (gPreviousInt == SIG_IGN) std::signal(SIGINT, SIG_IGN);
    gPreviousTerm = std::signal(SIGTERM, removePendingAndDie);
    if (gPreviousTerm == SIG_IGN) std::signal(SIGTERM, SIG_IGN);
    return true;
  }();
  (void)installed;
  for (auto& slot : gPending) {
    const char* empty = nullptr;
    if (slot.compare_exchange_strong(empty, path)) return;
  }
  // More outputs than slots: the file is still removed on any normal exit, only not on a signal.
}

void unregisterPending(const char* path) {
  for (auto& slot : gPending) {
    const char* expected = path;
    if (slot.compare_exchange_strong(expected, nullptr)) return;
  }
}

}  // namespace

OutputFile::OutputFile(const std::string& path) : path_(path) {
  if (path.empty()) throw InputError("", "output path is empty");
  const fs::path target(path);
  const fs::path folder = target.parent_path().empty() ? fs::path(".") : target.parent_path();
  std::error_code ec;
  if (!fs::is_directory(folder, ec))
    throw InputError(path, "cannot write: folder '" + folder.string() +
                               "' does not exist (create it first)");
  if (fs::is_directory(target, ec))
    throw InputError(path, "cannot write: this is a folder; give a file name");
  if (!target.has_filename()) throw InputError(path, "cannot write: no file name given");

  // Process id plus a counter: two runs, or two outputs of one run, never share a temp name.
  static std::atomic<unsigned> counter{0};
  // Built by append: GCC 12 at -O3 gives a false -Wrestrict on a chain of operator+.
  std::string temp = ".";
  temp.append(target.stem().string());
  temp.append(".partial-");
  temp.append(std::to_string(static_cast<long>(::getpid())));
  temp.append("-");
  temp.append(std::to_string(counter++));
  temp.append(target.extension().string());
  tempPath_ = (folder / temp).string();
  registerPending(tempPath_.c_str());
  file_ = std::fopen(tempPath_.c_str(), "wb");
  if (file_ == nullptr) {
    const int err = errno;
    unregisterPending(tempPath_.c_str());
    throw InputError(path, std::string("cannot write in folder '") + folder.string() +
                               "': " + std::strerror(err));
  }
}

OutputFile::~OutputFile() {
  if (file_ != nullptr) std::fclose(file_);
  if (!committed_) std::remove(tempPath_.c_str());
  unregisterPending(tempPath_.c_str());
}

void OutputFile::closeStream() {
  if (file_ == nullptr) return;
  const bool failed = std::fflush(file_) != 0 || std::ferror(file_) != 0;
  const int err = errno;
  const bool closeFailed = std::fclose(file_) != 0;
  file_ = nullptr;
  if (failed || closeFailed)
    throw InputError(path_, std::string("cannot write: ") + std::strerror(failed ? err : errno));
}

void OutputFile::commit() {
  if (file_ != nullptr) {
    // fsync: after a crash the renamed file holds either the old content or the complete new one.
    if (std::fflush(file_) == 0) ::fsync(::fileno(file_));
  }
  closeStream();
  if (std::rename(tempPath_.c_str(), path_.c_str()) != 0)
    throw InputError(path_, std::string("cannot replace the file: ") + std::strerror(errno));
  committed_ = true;
  unregisterPending(tempPath_.c_str());
}

// --- CSV ------------------------------------------------------------------------------------

void writeCsvHeader(std::FILE* out) {
  std::fputs("frame,time,body,x,y,z,qw,qx,qy,qz,vx,vy,vz,wx,wy,wz\n", out);
}

void writeCsvFrame(std::FILE* out, int frame, double time, const World& world) {
  for (int id = 0; id < world.bodyCount(); ++id) {
    if (!world.isActive(id)) continue;
    const BodyState& s = world.state(id);
    const Vec3 v = world.velocity(id);
    const Vec3 w = world.angularVelocity(id);
    std::fprintf(out,
                 "%d,%.17g,%d,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,"
                 "%.17g,%.17g\n",
                 frame, time, id, s.x.x(), s.x.y(), s.x.z(), s.q.w(), s.q.x(), s.q.y(), s.q.z(),
                 v.x(), v.y(), v.z(), w.x(), w.y(), w.z());
  }
}

// --- JSON and human summary -----------------------------------------------------------------

namespace {

std::string jsonString(const std::string& s) {
  std::string out = "\"";
  for (const char ch : s) {
    const auto c = static_cast<unsigned char>(ch);
    if (c == '"' || c == '\\') {
      out += '\\';
      out += ch;
    } else if (c < 0x20) {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\u%04x", c);
      out += buf;
    } else {
      out += ch;
    }
  }
  return out + "\"";
}

// JSON has no inf or nan; null says "no meaningful value" without breaking parsers.
std::string jsonNumber(double v) {
  if (!std::isfinite(v)) return "null";
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

std::string jsonCount(std::uint64_t v) { return std::to_string(v); }

}  // namespace

void writeSummaryJson(std::FILE* out, const std::string& scene, const RunSummary& s) {
  const std::pair<const char*, std::string> fields[] = {
      {"scene", jsonString(scene)},
      {"frames", std::to_string(s.frames)},
      {"steps", jsonCount(s.totals.steps)},
      {"dt_min", jsonNumber(s.totals.dtMin)},
      {"dt_max", jsonNumber(s.totals.dtMax)},
      {"wall_seconds", jsonNumber(s.wallSeconds)},
      {"sphere_tests", jsonCount(s.totals.sphereTests)},
      {"contacts", jsonCount(s.totals.contacts)},
      {"max_penetration_body_body", jsonNumber(s.maxPenetrationBodyBody)},
      {"max_penetration_body_ground", jsonNumber(s.maxPenetrationBodyGround)},
      {"tunnelled", std::to_string(s.tunnelled)},
      {"kinetic_energy", jsonNumber(s.kineticEnergy)},
      {"potential_energy", jsonNumber(s.potentialEnergy)},
      {"checksum", jsonString(s.checksumHex())},
      {"warnings", "{\"overlapping_releases\": " + jsonCount(s.totals.overlappingReleases) +
                       ", \"frozen_non_finite\": " + jsonCount(s.totals.nonFinite) +
                       ", \"floored_steps\": " + jsonCount(s.totals.floored) + "}"},
  };
  std::fputs("{\n", out);
  const std::size_t n = sizeof fields / sizeof fields[0];
  for (std::size_t i = 0; i < n; ++i)
    std::fprintf(out, "  \"%s\": %s%s\n", fields[i].first, fields[i].second.c_str(),
                 i + 1 < n ? "," : "");
  std::fputs("}\n", out);
}

void printSummary(std::FILE* out, const std::string& scene, const RunSummary& s) {
  std::fprintf(out, "%s: %d frames, %" PRIu64 " steps (dt %.3g .. %.3g s), %.2f s wall\n",
               scene.c_str(), s.frames, s.totals.steps, s.totals.dtMin, s.totals.dtMax,
               s.wallSeconds);
  std::fprintf(out, "  sphere tests %" PRIu64 ", contacts %" PRIu64 "\n", s.totals.sphereTests,
               s.totals.contacts);
  std::fprintf(out, "  max penetration: body-body %.3g m, body-ground %.3g m; tunnelled %d\n",
               s.maxPenetrationBodyBody, s.maxPenetrationBodyGround, s.tunnelled);
  std::fprintf(out, "  final energy: kinetic %.6g J, potential %.6g J\n", s.kineticEnergy,
               s.potentialEnergy);
  std::fprintf(out, "  checksum %s\n", s.checksumHex().c_str());
  // Things that explain surprising results; silent when all is well.
  if (s.totals.overlappingReleases > 0)
    std::fprintf(out,
                 "  warning: %" PRIu64 " bodies were released overlapping another body "
                 "(an emitter aimed into a pile?); their interpenetration is not the step's\n",
                 s.totals.overlappingReleases);
  if (s.totals.nonFinite > 0)
    std::fprintf(out, "  warning: %" PRIu64 " times a body's state went non-finite and it was frozen\n",
                 s.totals.nonFinite);
  if (s.totals.floored > 0)
    std::fprintf(out,
                 "  warning: %" PRIu64 " steps were held at the minimum step (a body moved faster "
                 "than 1e4 m/s)\n",
                 s.totals.floored);
}

// --- Progress -------------------------------------------------------------------------------

namespace {
constexpr double kQuietSeconds = 1.0;    // short runs print nothing
constexpr double kTtyRedraw = 0.1;       // s between in-place redraws
constexpr double kLogInterval = 5.0;     // s between lines when stderr is not a terminal

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

// --- Overrides ------------------------------------------------------------------------------

void applyLevelOverride(SceneSpec& spec, int level) {
  spec.level = level;
  for (ShapeSpec& s : spec.shapes) s.level.reset();
}

namespace {
// "0.005", or "1/120" as the paper writes steps; nothing unless finite and > 0.
std::optional<double> parseStepSeconds(const std::string& text) {
  auto parse = [](const std::string& s) -> std::optional<double> {
    if (s.empty()) return std::nullopt;
    char* end = nullptr;
    errno = 0;
    const double v = std::strtod(s.c_str(), &end);
    if (end != s.c_str() + s.size() || errno == ERANGE || !std::isfinite(v)) return std::nullopt;
    return v;
  };
  std::optional<double> v;
  if (const auto slash = text.find('/'); slash != std::string::npos) {
    const auto num = parse(text.substr(0, slash)), den = parse(text.substr(slash + 1));
    if (num && den && *den != 0) v = *num / *den;
  } else {
    v = parse(text);
  }
  if (v && std::isfinite(*v) && *v > 0) return v;
  return std::nullopt;
}
}  // namespace

std::string checkStepOption(const std::string& text) {
  if (text == "auto" || parseStepSeconds(text)) return "";
  return "expected 'auto' (eq. 20) or a fixed step in seconds > 0 (e.g. 0.005 or 1/120), got '" +
         text + "'";
}

void applyStepOverride(SceneSpec& spec, const std::string& text) {
  if (text == "auto") {
    spec.autoStep = true;
    spec.fixedStep = 0;
    return;
  }
  const auto v = parseStepSeconds(text);
  if (!v) throw InputError("", "--step: " + checkStepOption(text));
  spec.autoStep = false;
  spec.fixedStep = *v;
}

void applyColliderOverride(SceneSpec& spec, const std::string& method) {
  VF_ASSERT(method == "voxel" || method == "polygon");  // CLI11 checked it
  spec.collider = method == "polygon" ? ColliderMethod::kPolygon : ColliderMethod::kVoxel;
}

std::string checkSize(const std::string& text) {
  int w = 0, h = 0;
  char x = 0, extra = 0;
  if (std::sscanf(text.c_str(), "%d%c%d%c", &w, &x, &h, &extra) != 3 || (x != 'x' && x != 'X')) {
    return "size must be WxH, e.g. 1280x720";
  }
  if (w < 16 || h < 16 || w > 8192 || h > 8192) return "each side must be 16..8192 pixels";
  return "";
}

}  // namespace vf::cli

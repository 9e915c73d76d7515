#include "render/output/output_file.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <csignal>
#include <cstring>
#include <filesystem>
#include <mutex>
#include <set>
#include <system_error>
#include <vector>

#include "sim/core/error.h"

namespace vf {

namespace fs = std::filesystem;

namespace {

// Temporary files not yet committed, for the second signal. Slots hold pointers to each
// OutputFile's own path string; lock-free atomics are safe to read in a handler, and unlink()
// and raise() are async-signal-safe, so the handler does nothing else.
constexpr int kMaxPending = 64;
std::atomic<const char*> gPending[kMaxPending];
// Child processes running now that may still write temporary files: helper programs
// (runHelperProgram), ended with SIGKILL, and workers running voxfall's own code (forkWorker),
// sent the stop signal so that their own handlers remove their temporary files.
constexpr int kMaxChildren = 64;
std::atomic<pid_t> gHelpers[kMaxChildren];
std::atomic<pid_t> gWorkers[kMaxChildren];
std::atomic<int> gStopSignal{0};
std::atomic<bool> gGraceful{false};  // a command polls stopSignal() (installStopHandlers)

extern "C" void onStopSignal(int sig) {
  int none = 0;
  // The first signal to a command that polls: finish the frame in hand and stop.
  if (gGraceful.load() && gStopSignal.compare_exchange_strong(none, sig)) return;
  // Helpers first: one left running could write a temporary file after it was removed.
  for (auto& slot : gHelpers) {
    if (const pid_t pid = slot.load(); pid > 0) {
      ::kill(pid, SIGKILL);
      ::waitpid(pid, nullptr, 0);
    }
  }
  for (auto& slot : gWorkers) {
    if (const pid_t pid = slot.load(); pid > 0) {
      ::kill(pid, sig);  // its dispositions are this process's: it ends as this one does
      ::waitpid(pid, nullptr, 0);
    }
  }
  for (auto& slot : gPending) {
    if (const char* p = slot.load()) ::unlink(p);
  }
  std::signal(sig, SIG_DFL);
  std::raise(sig);
}

// Both signals go to onStopSignal from the first output or installStopHandlers() on.
void ensureHandlers() {
  static const bool installed = [] {
    if (std::signal(SIGINT, onStopSignal) == SIG_IGN) std::signal(SIGINT, SIG_IGN);
    if (std::signal(SIGTERM, onStopSignal) == SIG_IGN) std::signal(SIGTERM, SIG_IGN);
    return true;
  }();
  (void)installed;
}

void registerPending(const char* path) {
  for (auto& slot : gPending) {
    const char* empty = nullptr;
    if (slot.compare_exchange_strong(empty, path)) return;
  }
  // More outputs than slots: the file is still removed on any normal exit, only not on a
  // second signal.
}

void unregisterPending(const char* path) {
  for (auto& slot : gPending) {
    const char* expected = path;
    if (slot.compare_exchange_strong(expected, nullptr)) return;
  }
}

void registerChild(std::atomic<pid_t> (&slots)[kMaxChildren], pid_t pid) {
  for (auto& slot : slots) {
    pid_t empty = 0;
    if (slot.compare_exchange_strong(empty, pid)) return;
  }
}

void unregisterChild(std::atomic<pid_t> (&slots)[kMaxChildren], pid_t pid) {
  for (auto& slot : slots) {
    pid_t expected = pid;
    if (slot.compare_exchange_strong(expected, 0)) return;
  }
}

// fork() with the stop signals blocked until the child is in `slots`, so the handler always
// knows it. The child forgets its parent's children and gets the signal mask back.
pid_t forkRegistered(std::atomic<pid_t> (&slots)[kMaxChildren], sigset_t& previous) {
  ensureHandlers();
  sigset_t stops;
  sigemptyset(&stops);
  sigaddset(&stops, SIGINT);
  sigaddset(&stops, SIGTERM);
  ::sigprocmask(SIG_BLOCK, &stops, &previous);
  const pid_t child = ::fork();
  if (child == 0) {
    for (auto& slot : gHelpers) slot.store(0);
    for (auto& slot : gWorkers) slot.store(0);
    return 0;  // the caller restores the mask
  }
  if (child > 0) registerChild(slots, child);
  ::sigprocmask(SIG_SETMASK, &previous, nullptr);
  return child;
}

// In the child of runHelperProgram: output to `log`, then the program. Only async-signal-safe
// calls between fork and exec.
[[noreturn]] void execHelper(char* const* argv, const char* log, const sigset_t& mask) {
  std::signal(SIGINT, SIG_DFL);
  std::signal(SIGTERM, SIG_DFL);
  ::sigprocmask(SIG_SETMASK, &mask, nullptr);
  const int out = ::open(log, O_WRONLY | O_CREAT | O_TRUNC, 0644);
  const int in = ::open("/dev/null", O_RDONLY);
  if (out >= 0) {
    ::dup2(out, 1);
    ::dup2(out, 2);
  }
  if (in >= 0) ::dup2(in, 0);
  ::execvp(argv[0], argv);
  static const char kNotFound[] = "cannot run the program: not found or not executable\n";
  if (::write(2, kNotFound, sizeof kNotFound - 1) < 0) ::_exit(127);
  ::_exit(127);
}

// The process id in a temporary name ".STEM.partial-PID-N.EXT", or 0 if `name` is not one.
long partialOwner(const std::string& name) {
  const std::size_t at = name.rfind(".partial-");
  if (name.empty() || name[0] != '.' || at == std::string::npos) return 0;
  std::size_t end = at + 9;
  long pid = 0;
  while (end < name.size() && name[end] >= '0' && name[end] <= '9' && pid < 1000000000)
    pid = pid * 10 + (name[end++] - '0');
  return end < name.size() && name[end] == '-' ? pid : 0;
}

// Whether process `pid` is gone: no such process, or a zombie (it has exited; only its parent
// has not collected it yet, which an orphan in a container may never have done).
bool processGone(long pid) {
  if (::kill(static_cast<pid_t>(pid), 0) != 0) return errno == ESRCH;
  std::FILE* stat = std::fopen(("/proc/" + std::to_string(pid) + "/stat").c_str(), "r");
  if (stat == nullptr) return false;
  char state = 0;
  const bool read = std::fscanf(stat, "%*d (%*[^)]) %c", &state) == 1;
  std::fclose(stat);
  return read && state == 'Z';
}

// removeStalePartials() once per folder and process.
void cleanOnce(const fs::path& folder) {
  static std::mutex mutex;
  static std::set<std::string> cleaned;
  std::error_code ec;
  const std::string key = fs::weakly_canonical(folder, ec).string();
  std::lock_guard<std::mutex> lock(mutex);
  if (cleaned.insert(key).second) removeStalePartials(folder.string());
}

}  // namespace

void removeStalePartials(const std::string& folder) {
  std::error_code ec;
  for (fs::directory_iterator it(folder, ec), end; !ec && it != end; it.increment(ec)) {
    const long pid = partialOwner(it->path().filename().string());
    // A live process's files (another run writing into the same folder) are never touched.
    if (pid <= 0 || pid == static_cast<long>(::getpid())) continue;
    if (processGone(pid)) {
      std::error_code rm;
      fs::remove(it->path(), rm);
    }
  }
}

OutputRules replaceOutputs() { return OutputRules{Overwrite::always, {}}; }

void checkOutputPath(const std::string& path, const OutputRules& rules) {
  if (path.empty()) throw InputError("", "output path is empty");
  const fs::path target(path);
  if (!target.has_filename()) throw InputError(path, "cannot write: no file name given");
  std::error_code ec;
  if (fs::is_directory(target, ec))
    throw InputError(path, "cannot write: this is a folder; give a file name");
  if (!fs::exists(target, ec)) return;
  for (const std::string& input : rules.inputs) {
    if (fs::equivalent(target, input, ec))
      throw InputError(path, "is an input of this run (" + input + "); it is never overwritten");
  }
  switch (rules.overwrite) {
    case Overwrite::always:
      return;
    case Overwrite::never:
      throw InputError(path, "already exists; not overwritten (-n)");
    case Overwrite::refuse:
      throw InputError(path, "already exists; use -y to overwrite it (or -n to never overwrite)");
  }
}

OutputFile::OutputFile(const std::string& path, const OutputRules& rules) : path_(path) {
  checkOutputPath(path, rules);
  const fs::path target(path);
  const fs::path folder = target.parent_path().empty() ? fs::path(".") : target.parent_path();
  std::error_code ec;
  fs::create_directories(folder, ec);
  if (ec)
    throw InputError(path, "cannot create the folder '" + folder.string() + "': " + ec.message());
  cleanOnce(folder);

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
  ensureHandlers();
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

int runHelperProgram(const std::vector<std::string>& argv, const std::string& logPath) {
  std::vector<char*> args;
  for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  sigset_t previous;
  const pid_t child = forkRegistered(gHelpers, previous);
  if (child == 0) execHelper(args.data(), logPath.c_str(), previous);
  if (child < 0)
    throw InputError(argv.front(), std::string("cannot start: ") + std::strerror(errno));
  int status = 0;
  while (::waitpid(child, &status, 0) < 0 && errno == EINTR) {
  }
  unregisterChild(gHelpers, child);
  return status;
}

pid_t forkWorker() {
  sigset_t previous;
  const pid_t child = forkRegistered(gWorkers, previous);
  if (child == 0) ::sigprocmask(SIG_SETMASK, &previous, nullptr);
  return child;
}

void workerEnded(pid_t pid) { unregisterChild(gWorkers, pid); }

void installStopHandlers() {
  gGraceful.store(true);
  ensureHandlers();
}

int stopSignal() { return gStopSignal.load(); }

std::string signalName(int signal) {
  if (signal == SIGINT) return "SIGINT";
  if (signal == SIGTERM) return "SIGTERM";
  return "signal " + std::to_string(signal);
}

}  // namespace vf

// Running the built voxfall binary from a test, as a user would: a whole file read back, and
// `voxfall ARGS` run in a folder with its exit code, stdout and stderr.
#pragma once

#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <regex>
#include <sstream>
#include <string>
#include <thread>
#include <utility>
#include <vector>

namespace vf::test {

// The bytes of a file ("" if it cannot be read).
inline std::string readFile(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// An empty scratch folder under the system's temporary folder, named after `prefix`, this
// process and the running test (`name`), so tests run in parallel never share one.
inline std::filesystem::path scratchFolder(const std::string& prefix, const std::string& name) {
  const std::filesystem::path dir = std::filesystem::temp_directory_path() /
                                    (prefix + "_" + std::to_string(::getpid()) + "_" + name);
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

// The shipped cubes scene copied from the folder `scenes` into `dir` (cubes.toml, lasting 2 s,
// and its mesh, an input of the run), and beside it, for each (file name, seconds), the same
// scene lasting that long: a run long enough for a signal to land while it works.
inline void copyCubesScene(const std::filesystem::path& scenes, const std::filesystem::path& dir,
                           const std::vector<std::pair<std::string, int>>& longer = {}) {
  std::filesystem::create_directories(dir / "meshes");
  std::filesystem::copy_file(scenes / "meshes/cube.obj", dir / "meshes/cube.obj");
  const std::string text = readFile(scenes / "cubes.toml");
  std::ofstream(dir / "cubes.toml") << text;
  for (const auto& [name, seconds] : longer)
    std::ofstream(dir / name) << std::regex_replace(text, std::regex("duration = 2\\.0"),
                                                    "duration = " + std::to_string(seconds) + ".0");
}

struct CommandResult {
  int code = -1;  // exit code; -1 if the process did not exit normally
  std::string out, err;
};

// Runs `EXE ARGS` in `dir` (stdin from /dev/null). ARGS is shell text: quote paths in it.
inline CommandResult runVoxfall(const std::string& exe, const std::filesystem::path& dir,
                                const std::string& args) {
  const std::filesystem::path out = dir / ".voxfall_stdout", err = dir / ".voxfall_stderr";
  const std::string cmd = "cd '" + dir.string() + "' && '" + exe + "' " + args + " >'" +
                          out.string() + "' 2>'" + err.string() + "' </dev/null";
  const int status = std::system(cmd.c_str());
  CommandResult r;
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  r.out = readFile(out);
  r.err = readFile(err);
  std::filesystem::remove(out);
  std::filesystem::remove(err);
  return r;
}

// Starts `EXE ARGS...` in `dir` as a child process, its stdout to /dev/null and its stderr to
// `stderrFile` in `dir` (or /dev/null when empty), and returns its process id without waiting:
// for tests that signal or kill a run part-way.
inline pid_t startVoxfall(const std::string& exe, const std::filesystem::path& dir,
                          const std::vector<std::string>& args,
                          const std::string& stderrFile = "") {
  const pid_t child = ::fork();
  if (child != 0) return child;
  // As a shell's foreground command: a test run as a background job ignores SIGINT, and the
  // command would inherit that and never see the signal a test sends.
  ::signal(SIGINT, SIG_DFL);
  ::signal(SIGTERM, SIG_DFL);
  if (::chdir(dir.c_str()) != 0) ::_exit(126);
  const int null = ::open("/dev/null", O_WRONLY);
  const int err =
      stderrFile.empty() ? null : ::open(stderrFile.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  ::dup2(null, 1);
  ::dup2(err, 2);
  std::vector<char*> argv{const_cast<char*>(exe.c_str())};
  for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  ::execv(exe.c_str(), argv.data());
  ::_exit(127);
}

// Starts `EXE ARGS...` as startVoxfall does, sends `sig` once `ready()` holds (or after a
// minute), and returns the child's wait status.
inline int interruptVoxfall(const std::string& exe, const std::filesystem::path& dir,
                            const std::vector<std::string>& args, int sig,
                            const std::function<bool()>& ready,
                            const std::string& stderrFile = "") {
  const pid_t child = startVoxfall(exe, dir, args, stderrFile);
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  while (!ready() && std::chrono::steady_clock::now() < deadline)
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  ::kill(child, sig);
  int status = 0;
  ::waitpid(child, &status, 0);
  return status;
}

}  // namespace vf::test

// Running the built voxfall binary from a test, as a user would: a whole file read back, and
// `voxfall ARGS` run in a folder with its exit code, stdout and stderr.
#pragma once

#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

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

}  // namespace vf::test

// Errors at the boundary (scene files, meshes, shaders, file I/O): one exception type that
// carries where the problem is, so the CLI can report it once and exit non-zero.
// Programmer errors use VF_ASSERT; numerical trouble inside a step is counted in StepStats.
#pragma once

#include <stdexcept>
#include <string>

namespace vf {

// Bad input. what() is the full message: "WHERE: MESSAGE", where WHERE is "file",
// "file:line" or "file:line:column" (empty location gives just MESSAGE).
class InputError : public std::runtime_error {
 public:
  InputError(const std::string& where, const std::string& message);
  const std::string& where() const { return where_; }
  const std::string& message() const { return message_; }

 private:
  std::string where_;
  std::string message_;
};

// "file:line:column" from parts; line or column 0 are left out.
std::string sourceLocation(const std::string& file, int line = 0, int column = 0);

}  // namespace vf

// Kept on in RelWithDebInfo (the default build): a failed invariant is a bug in voxfall.
#define VF_ASSERT(cond)                                                 \
  do {                                                                  \
    if (!(cond)) ::vf::detail::assertFailed(#cond, __FILE__, __LINE__); \
  } while (0)

namespace vf::detail {
[[noreturn]] void assertFailed(const char* cond, const char* file, int line);
}

#include "sim/core/error.h"

#include <cstdio>
#include <cstdlib>

namespace vf {

namespace {
std::string joined(const std::string& where, const std::string& message) {
  if (where.empty()) return message;
  std::string s;
  s.reserve(where.size() + 2 + message.size());
  s.append(where).append(": ").append(message);
  return s;
}
}  // namespace

InputError::InputError(const std::string& where, const std::string& message)
    : std::runtime_error(joined(where, message)), where_(where), message_(message) {}

std::string sourceLocation(const std::string& file, int line, int column) {
  std::string s = file;
  if (line > 0) {
    s.append(":").append(std::to_string(line));
    if (column > 0) s.append(":").append(std::to_string(column));
  }
  return s;
}

namespace detail {
void assertFailed(const char* cond, const char* file, int line) {
  std::fprintf(stderr, "voxfall: internal error: assertion '%s' failed at %s:%d\n", cond, file,
               line);
  std::abort();
}
}  // namespace detail

}  // namespace vf

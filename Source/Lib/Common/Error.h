#pragma once
// Two error channels (../shared/DESIGN.md): InputError for bad external input, caught once in main();
// VS_CHECK for programming errors, always on, aborting with file:line.
#include <stdexcept>
#include <string>

namespace vs {

// Bad input from outside: a file, a key, a value, camera data. The message names where and what was
// expected; main() prints it on stderr and exits non-zero.
class InputError : public std::runtime_error {
public:
  explicit InputError(const std::string& message) : std::runtime_error(message) {}
};

// One number formatted by a printf pattern with one double ("%g", "%.17g"), for messages and printouts.
std::string formatNumber(const char* pattern, double value);

[[noreturn]] void checkFailed(const char* expression, const char* file, int line, const char* message);

}  // namespace vs

// Always-on invariant check for bugs (never for bad input).
#define VS_CHECK(cond)                                                        \
  do {                                                                        \
    if (!(cond)) ::vs::checkFailed(#cond, __FILE__, __LINE__, nullptr);       \
  } while (0)
#define VS_CHECK_MSG(cond, msg)                                               \
  do {                                                                        \
    if (!(cond)) ::vs::checkFailed(#cond, __FILE__, __LINE__, (msg));         \
  } while (0)

#include "Common/Error.h"

#include <cstdio>
#include <cstdlib>

namespace vs {

void checkFailed(const char* expression, const char* file, int line, const char* message) {
  std::fprintf(stderr, "%s:%d: internal error: check failed: %s%s%s\n", file, line, expression,
               message ? ": " : "", message ? message : "");
  std::fflush(stderr);
  std::abort();
}

}  // namespace vs

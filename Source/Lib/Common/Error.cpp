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

std::string formatNumber(const char* pattern, double value) {
  char text[128];
  std::snprintf(text, sizeof text, pattern, value);
  return text;
}

}  // namespace vs

// Programmer errors (a broken REQUIRES contract): JUGGLE_CHECK(condition) << nothing; it prints
// the file, line and condition (and an optional message) to stderr and aborts. User input and
// run-time failures return absl::Status instead (docs/DESIGN.md).
#ifndef JUGGLE_COMMON_CHECK_H_
#define JUGGLE_COMMON_CHECK_H_

#include <cstdio>
#include <cstdlib>

#define JUGGLE_CHECK(condition, message)                                                  \
  do {                                                                                    \
    if (!(condition)) {                                                                   \
      std::fprintf(stderr, "%s:%d: check failed: %s: %s\n", __FILE__, __LINE__, #condition, \
                   message);                                                              \
      std::abort();                                                                       \
    }                                                                                     \
  } while (0)

#endif  // JUGGLE_COMMON_CHECK_H_

// For tests of permission errors: root writes into read-only folders, so a test that needs a
// refused write drops root first. Call only in a child process (a gtest death test's
// statement): the change is permanent for the process.
#ifndef JUGGLE_COMMON_TESTING_UNPRIVILEGED_H_
#define JUGGLE_COMMON_TESTING_UNPRIVILEGED_H_

#include <unistd.h>

#include <cstdio>
#include <cstdlib>

namespace juggle {

// Becomes the `nobody` user (65534) when running as root; exits 99 if that fails.
inline void DropRootPrivileges() {
  if (::geteuid() != 0) return;
  if (::setgid(65534) != 0 || ::setuid(65534) != 0) {
    std::fprintf(stderr, "cannot drop root privileges\n");
    std::exit(99);
  }
}

}  // namespace juggle

#endif  // JUGGLE_COMMON_TESTING_UNPRIVILEGED_H_

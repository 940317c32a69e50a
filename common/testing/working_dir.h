// For tests of what a process reads relative to its working folder: changes the working folder
// for one scope and changes it back at the end. Not thread-safe: the working folder is the
// process's.
#ifndef JUGGLE_COMMON_TESTING_WORKING_DIR_H_
#define JUGGLE_COMMON_TESTING_WORKING_DIR_H_

#include <unistd.h>

#include <climits>
#include <string>

#include "gtest/gtest.h"

namespace juggle {

class ScopedWorkingDir {
 public:
  explicit ScopedWorkingDir(const std::string& dir) {
    char buf[PATH_MAX];
    if (::getcwd(buf, sizeof(buf)) != nullptr) previous_ = buf;
    EXPECT_EQ(::chdir(dir.c_str()), 0) << "cannot enter " << dir;
  }
  ~ScopedWorkingDir() {
    EXPECT_EQ(::chdir(previous_.c_str()), 0) << "cannot return to " << previous_;
  }
  ScopedWorkingDir(const ScopedWorkingDir&) = delete;
  ScopedWorkingDir& operator=(const ScopedWorkingDir&) = delete;

 private:
  std::string previous_;
};

}  // namespace juggle

#endif  // JUGGLE_COMMON_TESTING_WORKING_DIR_H_

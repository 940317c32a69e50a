// Fresh scratch directories under $TMPDIR (default: the system temporary directory), for
// tests and benchmarks.
#ifndef JUGGLE_COMMON_TESTING_TEMP_DIR_H_
#define JUGGLE_COMMON_TESTING_TEMP_DIR_H_

#include <stdlib.h>

#include <cstdlib>
#include <string>
#include <vector>

namespace juggle {

// Creates <tmpdir>/<prefix>XXXXXX and returns its path ("" if it could not be created).
inline std::string MakeTempDir(const std::string& prefix) {
  const char* base = std::getenv("TMPDIR");
  std::string pattern = std::string(base && *base ? base : P_tmpdir) + "/" + prefix + "XXXXXX";
  std::vector<char> buf(pattern.begin(), pattern.end());
  buf.push_back('\0');
  return ::mkdtemp(buf.data()) ? std::string(buf.data()) : std::string();
}

}  // namespace juggle

#endif  // JUGGLE_COMMON_TESTING_TEMP_DIR_H_

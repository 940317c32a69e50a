// Whole-file reads and checked writes: the project's one place that turns a path into bytes or
// bytes into a file. Every error names the path and the reason (errno text), with one status
// code per cause: NOT_FOUND (no such file or folder), PERMISSION_DENIED (no write permission,
// read-only file system), RESOURCE_EXHAUSTED (disk full, quota), INVALID_ARGUMENT (a folder, a
// device or a file above the size limit where a regular file is read), INTERNAL (anything
// else). Thread-compatible: AppendFile is used by one thread; the functions are reentrant.
#ifndef JUGGLE_COMMON_FILE_IO_H_
#define JUGGLE_COMMON_FILE_IO_H_

#include <memory>
#include <string>
#include <string_view>

#include "absl/status/status.h"
#include "absl/status/statusor.h"

namespace juggle {

// Reads a whole regular file of at most 1 GiB (a path naming /dev/zero or a FIFO must not hang).
absl::StatusOr<std::string> ReadFile(const std::string& path);

// Creates or truncates `path` and writes `bytes`; every write and the close are checked.
absl::Status WriteFile(const std::string& path, std::string_view bytes);

// Writes `bytes` to `path` so that a reader sees the old file or the new one, never a part:
// <path>.tmp, fsync, rename, fsync of the folder.
absl::Status WriteFileAtomically(const std::string& path, std::string_view bytes);

// Fails early, with the reason, when `path` cannot be created or written. Leaves no trace: an
// existing file is not modified, a file it had to create is removed. INVALID_ARGUMENT for "".
absl::Status CheckWritable(const std::string& path);

// A file opened for appending (created if missing). Each Append writes all its bytes and checks
// the result, so a full disk or a revoked permission is an error at the write that failed.
class AppendFile {
 public:
  static absl::StatusOr<std::unique_ptr<AppendFile>> Open(const std::string& path);
  ~AppendFile();
  AppendFile(const AppendFile&) = delete;
  AppendFile& operator=(const AppendFile&) = delete;

  absl::Status Append(std::string_view bytes);
  const std::string& path() const { return path_; }

 private:
  AppendFile(std::string path, int fd) : path_(std::move(path)), fd_(fd) {}
  std::string path_;
  int fd_;
};

}  // namespace juggle

#endif  // JUGGLE_COMMON_FILE_IO_H_

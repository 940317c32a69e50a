// Checkpoint files: named byte sections in one file with a checksum, written atomically
// (temporary file, fsync, rename). A directory keeps the newest few; loading falls back to the
// newest file that reads cleanly, so a truncated or corrupted write never loses a run.
#ifndef JUGGLE_LEARNER_CHECKPOINT_H_
#define JUGGLE_LEARNER_CHECKPOINT_H_

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "absl/status/statusor.h"
#include "common/checksum.h"  // Fnv1a64, the checkpoint checksum

namespace juggle {

using Sections = std::map<std::string, std::string>;

// Writes `sections` to `path` atomically. INTERNAL / PERMISSION_DENIED style errors from I/O.
absl::Status WriteCheckpointFile(const std::string& path, const Sections& sections);

// Reads a checkpoint. NOT_FOUND if missing; DATA_LOSS (naming the file and what is wrong) if
// truncated, corrupted (checksum mismatch) or not a checkpoint.
absl::StatusOr<Sections> ReadCheckpointFile(const std::string& path);
// The same for bytes already read; `path` only names them in errors.
absl::StatusOr<Sections> ParseCheckpoint(const std::string& bytes, const std::string& path);

class CheckpointDir {
 public:
  // Files are <dir>/ckpt-<iteration, 10 digits>.jglc; the newest `keep` are kept.
  explicit CheckpointDir(std::string dir, int keep = 3);

  // Saves and prunes. Returns the file's path.
  absl::StatusOr<std::string> Save(int64_t iteration, const Sections& sections);

  struct Loaded {
    std::string path;
    Sections sections;
    std::vector<std::string> skipped;  // "path: reason" for newer files that failed to read
  };
  // The newest checkpoint that reads cleanly. NOT_FOUND if there is none.
  absl::StatusOr<Loaded> LoadLatest() const;

  // Checkpoint paths, newest first.
  std::vector<std::string> List() const;
  const std::string& dir() const { return dir_; }

 private:
  std::string dir_;
  int keep_;
};

}  // namespace juggle

#endif  // JUGGLE_LEARNER_CHECKPOINT_H_

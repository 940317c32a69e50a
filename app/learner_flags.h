// The flags `juggle train` and `juggle learner` share, and the LearnerOptions they make:
// config, run directory, --resume / --init_from, limits, progress reporting.
#ifndef JUGGLE_APP_LEARNER_FLAGS_H_
#define JUGGLE_APP_LEARNER_FLAGS_H_

#include <cstdint>
#include <string>

#include "absl/status/statusor.h"
#include "app/command.h"
#include "learner/learner_server.h"

namespace juggle {

struct LearnerFlags {
  std::string config;     // empty: the resumed run's stored copy, else configs/right_foot.textproto
  std::string run_dir;    // empty: runs/<config name>
  bool resume = false;
  bool resume_if_any = false;  // resume when the run directory has a checkpoint, else start
  std::string init_from;  // a checkpoint (file or run directory) a new run starts from
  int64_t iterations = 0;
  double minutes = 0;
  int metrics_port = -1;
  int64_t seed = -1;      // -1: the config's seed
};

void AddLearnerFlags(CLI::App* cmd, LearnerFlags* flags);

// Loads the config and prepares the run directory (copying --init_from's checkpoint into it).
// A resumed run continues under the config stored in its newest checkpoint unless --config is
// given (then under that one, with a note on stderr when it differs from the stored copy).
// The learner writes the run log, <run_dir>/metrics.jsonl, itself (learner/run_log.h).
absl::StatusOr<LearnerOptions> MakeLearnerOptions(const LearnerFlags& flags);

}  // namespace juggle

#endif  // JUGGLE_APP_LEARNER_FLAGS_H_

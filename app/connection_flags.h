// The keepalive and reconnect flags of `juggle worker` (and `juggle-worker`) and `juggle
// learner` (common/connection_settings.h; docs/reliability.md, "Network faults"). Each range
// is checked at parsing (exit 2 naming the flag); what involves two flags (backoffs) by
// Validate() when the command runs.
#ifndef JUGGLE_APP_CONNECTION_FLAGS_H_
#define JUGGLE_APP_CONNECTION_FLAGS_H_

#include <CLI/CLI.hpp>

#include "common/connection_settings.h"

namespace juggle {

void AddWorkerConnectionFlags(CLI::App* cmd, WorkerConnectionSettings* settings);
void AddLearnerConnectionFlags(CLI::App* cmd, LearnerConnectionSettings* settings);

}  // namespace juggle

#endif  // JUGGLE_APP_CONNECTION_FLAGS_H_

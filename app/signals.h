// SIGINT/SIGTERM set a process-wide stop flag that long-running commands poll.
#ifndef JUGGLE_APP_SIGNALS_H_
#define JUGGLE_APP_SIGNALS_H_

#include <atomic>

namespace juggle {

// Installs the handlers (idempotent) and returns the flag they set.
std::atomic<bool>* InstallStopSignals();

}  // namespace juggle

#endif  // JUGGLE_APP_SIGNALS_H_

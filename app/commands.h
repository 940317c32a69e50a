// Subcommands of the `juggle` binary. Each returns a process exit code and prints its own
// errors; main() only dispatches.
#ifndef JUGGLE_APP_COMMANDS_H_
#define JUGGLE_APP_COMMANDS_H_

namespace juggle {

int RunSimulate(int argc, char** argv, int first, bool as_train);
int RunCheckConfig(int argc, char** argv, int first);
int RunBenchSim(int argc, char** argv, int first);

}  // namespace juggle

#endif  // JUGGLE_APP_COMMANDS_H_

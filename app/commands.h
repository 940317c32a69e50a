// Subcommands of the `juggle` binary. Each returns a process exit code and prints its own
// errors; main() only dispatches.
#ifndef JUGGLE_APP_COMMANDS_H_
#define JUGGLE_APP_COMMANDS_H_

namespace juggle {

int RunSimulate(int argc, char** argv, int first);
int RunTrain(int argc, char** argv, int first);
int RunLearner(int argc, char** argv, int first);
int RunWorkerCommand(int argc, char** argv, int first);
int RunEval(int argc, char** argv, int first);
int RunCheckConfig(int argc, char** argv, int first);
int RunBenchSim(int argc, char** argv, int first);
int RunBenchMoe(int argc, char** argv, int first);
int RunBenchIngest(int argc, char** argv, int first);
int RunBenchBroadcast(int argc, char** argv, int first);
int RunBenchLocal(int argc, char** argv, int first);
int RunRender(int argc, char** argv, int first);
int RunSiteswap(int argc, char** argv, int first);
int RunToss(int argc, char** argv, int first);
int RunExportPolicy(int argc, char** argv, int first);

}  // namespace juggle

#endif  // JUGGLE_APP_COMMANDS_H_

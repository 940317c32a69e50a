// Every `juggle` subcommand's Add function (app/<name>_command.cc), for main.cc's one list.
#ifndef JUGGLE_APP_COMMANDS_H_
#define JUGGLE_APP_COMMANDS_H_

#include "app/command.h"

namespace juggle {

CommandBody AddTrainCommand(CLI::App* cmd);
CommandBody AddLearnerCommand(CLI::App* cmd);
CommandBody AddWorkerCommand(CLI::App* cmd);
CommandBody AddEvalCommand(CLI::App* cmd);
CommandBody AddSimulateCommand(CLI::App* cmd);
CommandBody AddCheckConfigCommand(CLI::App* cmd);
CommandBody AddRenderCommand(CLI::App* cmd);
CommandBody AddSiteswapCommand(CLI::App* cmd);
CommandBody AddTossCommand(CLI::App* cmd);
CommandBody AddExportPolicyCommand(CLI::App* cmd);
CommandBody AddReplayCommand(CLI::App* cmd);
CommandBody AddPlayCommand(CLI::App* cmd);
CommandBody AddExportBvhCommand(CLI::App* cmd);
CommandBody AddBenchCommand(CLI::App* cmd);
CommandBody AddDashboardCommand(CLI::App* cmd);
CommandBody AddLabelSpreadCommand(CLI::App* cmd);
CommandBody AddFitDemosCommand(CLI::App* cmd);

}  // namespace juggle

#endif  // JUGGLE_APP_COMMANDS_H_

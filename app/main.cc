// juggle: train physically simulated characters to juggle a ball. One list of subcommands;
// `juggle --help` and `juggle <command> --help` come from it.
#include "app/command.h"
#include "app/commands.h"

namespace {

using juggle::Command;

const Command kCommands[] = {
    {"train", "train locally: a learner and its workers in one process over loopback",
     juggle::AddTrainCommand},
    {"learner", "the learner process of a cluster run (gRPC, /metrics, checkpoints)",
     juggle::AddLearnerCommand},
    {"worker", "a simulation worker of a cluster run (also the juggle-worker binary)",
     juggle::AddWorkerCommand},
    {"eval", "evaluate a checkpoint (mean action) or the zero-action baseline",
     juggle::AddEvalCommand},
    {"simulate", "run an env pool with zero or random actions and report episode stats",
     juggle::AddSimulateCommand},
    {"check-config", "load and validate a run config and its model; print a summary",
     juggle::AddCheckConfigCommand},
    {"render", "render a rollout to MP4/PNG (+ contact sheet); record and replay",
     juggle::AddRenderCommand},
    {"siteswap", "toss-juggling siteswaps: validity, state, throw schedule, transitions",
     juggle::AddSiteswapCommand},
    {"toss", "juggle a siteswap with trained catch/throw policies; --eval: the protocol",
     juggle::AddTossCommand},
    {"export-policy", "write a checkpoint's policy without its trainer (torch-free)",
     juggle::AddExportPolicyCommand},
    {"replay", "write a recording as a self-contained 3D HTML page (or serve it)",
     juggle::AddReplayCommand},
    {"play", "the character live in the browser: choose skills, poke the ball (docs/play.md)",
     juggle::AddPlayCommand},
    {"export-bvh", "write a recording's character motion as BVH (+ the balls as CSV)",
     juggle::AddExportBvhCommand},
    {"dashboard", "render a run's dashboard (metrics.jsonl), or an evaluation's graph (--eval), as one self-contained HTML file",
     juggle::AddDashboardCommand},
    {"bench", "benchmarks that print ratios measured in one run (docs/performance.md)",
     juggle::AddBenchCommand},
    {"label-spread", "how much the planner's labels vary at one state (docs/planner.md)",
     juggle::AddLabelSpreadCommand},
    {"fit-demos", "offline cloning of a run's demonstrations: fit and held-out error (docs/learning.md)",
     juggle::AddFitDemosCommand},
};
constexpr int kNumCommands = sizeof(kCommands) / sizeof(kCommands[0]);

}  // namespace

int main(int argc, char** argv) {
  CLI::App app("juggle: train physically simulated characters to juggle (docs/DESIGN.md)",
               "juggle");
  app.require_subcommand(1);
  app.footer("juggle <command> --help lists a command's flags.");
  juggle::CommandBody bodies[kNumCommands];
  const juggle::CommandBody* body_ptrs[kNumCommands];
  CLI::App* subcommands[kNumCommands];
  for (int i = 0; i < kNumCommands; ++i) {
    subcommands[i] = app.add_subcommand(kCommands[i].name, kCommands[i].help);
    bodies[i] = kCommands[i].add(subcommands[i]);
    body_ptrs[i] = &bodies[i];
  }
  return juggle::ParseAndRun(&app, argc, argv, body_ptrs, subcommands, kNumCommands);
}

// `juggle label-spread`: how much the planner's labels vary at one state (planner/label_spread.h,
// docs/planner.md "Label spread"): the floor of a student's held-out label error.
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "absl/strings/str_cat.h"
#include "app/commands.h"
#include "app/planner_flags.h"
#include "app/policy_source.h"
#include "common/file_io.h"
#include "envs/registry.h"
#include "learner/demo_buffer.h"
#include "planner/label_spread.h"

namespace juggle {

namespace {

// The kept rows as a demonstration buffer, in the order they were visited (juggle fit-demos
// reads it).
absl::Status WriteRows(const planner::LabelSpreadReport& r, int obs_dim, int label_dim,
                       const std::vector<float>& labels, const std::string& path) {
  const int64_t rows = static_cast<int64_t>(r.row_obs.size()) / obs_dim;
  DemoBuffer demos(std::max<int64_t>(rows, 1), obs_dim, label_dim);
  demos.AddPairs(r.row_obs.data(), labels.data(), rows);
  return WriteFileAtomically(path, demos.Serialize());
}

// The folder `path` will be written to, made before a long measurement rather than after it.
absl::Status MakeParentFolder(const std::string& path) {
  const std::filesystem::path parent = std::filesystem::path(path).parent_path();
  std::error_code error;
  if (!parent.empty()) std::filesystem::create_directories(parent, error);
  if (error) {
    return absl::PermissionDeniedError(
        absl::StrCat("cannot create ", parent.string(), ": ", error.message()));
  }
  return absl::OkStatus();
}

}  // namespace

CommandBody AddLabelSpreadCommand(CLI::App* cmd) {
  struct Flags {
    std::string config = "configs/learning/guided_cheap_consistent.textproto";
    planner::LabelSpreadOptions options;
    PlannerFlags planner;
    std::string student;
    std::string dump_demos;
    std::string dump_kicks;
  };
  auto f = std::make_shared<Flags>();
  cmd->add_option("--config", f->config, "run config with a planner section (the teacher's)")
      ->capture_default_str();
  cmd->add_option("--episodes", f->options.episodes, "episodes the planner juggles")
      ->check(CLI::Range(1, 1000))
      ->capture_default_str();
  cmd->add_option("--seconds", f->options.seconds, "simulated seconds per episode")
      ->check(CLI::Range(0.1, 3600.0))
      ->capture_default_str();
  cmd->add_option("--forks", f->options.forks,
                  "re-plans of each re-plan state (other streams); 0: no spread, only labels")
      ->check(CLI::Range(0, 64))
      ->capture_default_str();
  cmd->add_option("--seed", f->options.seed, "episode starts: streams (seed, 0, episode)")
      ->capture_default_str();
  cmd->add_option("--min-label-std", f->options.min_label_std,
                  "floor of the label spread in the weights (imitation.min_label_std)")
      ->capture_default_str();
  cmd->add_option("--student", f->student,
                  "a policy (checkpoint, run directory or .jglpolicy) whose mean action is "
                  "compared with the labels at every visited state");
  cmd->add_option("--student-mix", f->options.student_mix,
                  "execute label + MIX*(student - label): 0 the planner drives, 1 the student "
                  "(how much of the student's error the juggle tolerates)")
      ->check(CLI::Range(0.0, 1.0))
      ->capture_default_str();
  cmd->add_option("--expert-noise", f->options.expert_noise,
                  "DART: Gaussian noise of this std (policy units) on every executed action; "
                  "the labels stay the planner's clean actions")
      ->check(CLI::Range(0.0, 2.0))
      ->capture_default_str();
  cmd->add_option("--noise-hold", f->options.noise_hold_steps,
                  "control steps each noise draw is held (1: independent per step; more: an "
                  "offset like a student's bias)")
      ->check(CLI::Range(1, 100000))
      ->capture_default_str();
  cmd->add_option("--dump-demos", f->dump_demos,
                  "also write every visited state with the planner's action as a demonstration "
                  "buffer (juggle fit-demos reads it)");
  cmd->add_option("--dump-kicks", f->dump_kicks,
                  "also write every visited state with the planner's 5 kick variables of the "
                  "current cycle (at its last re-plan) as labels, the same way");
  AddPlannerFlags(cmd, &f->planner);
  return [f] {
    absl::StatusOr<LoadedConfig> config = LoadRunConfig(f->config);
    if (!config.ok()) return Fail(config.status());
    if (absl::Status s = ApplyPlannerFlags(f->planner, &*config); !s.ok()) return Fail(s);
    absl::StatusOr<std::shared_ptr<const EnvSpec>> spec = CreateEnvSpec(*config);
    if (!spec.ok()) return Fail(spec.status());
    std::optional<PolicySource> student;
    if (!f->student.empty()) {
      absl::StatusOr<PolicySource> s = LoadPolicySource(f->student, "");
      if (!s.ok()) return Fail(s.status());
      student = *std::move(s);
      f->options.student = student->policy.get();
    }
    f->options.keep_rows = !f->dump_demos.empty() || !f->dump_kicks.empty();
    for (const std::string& path : {f->dump_demos, f->dump_kicks}) {
      if (path.empty()) continue;
      if (absl::Status s = MakeParentFolder(path); !s.ok()) return Fail(s);
    }
    const config::PlannerConfig& pc = config->run.planner();
    std::printf("planner: %d samples x %d iterations, horizon %d, re-plan every %d, kick "
                "consistency %g; %d forks per re-plan state\n",
                pc.samples(), pc.iterations(), pc.horizon_steps(), pc.replan_every(),
                pc.soccer_juggle().cost().kick_consistency(), f->options.forks);
    absl::StatusOr<planner::LabelSpreadReport> r = planner::MeasureLabelSpread(
        *spec, *config, f->options, [](const std::string& line) {
          std::printf("%s\n", line.c_str());
          std::fflush(stdout);
        });
    if (!r.ok()) return Fail(r.status());
    std::printf("%-7s %10s %10s %13s\n", "action", "label_std", "fork_std", "student_rmse");
    for (size_t i = 0; i < r->label_std.size(); ++i) {
      std::printf("%-7zu %10.4f %10.4f %13.4f\n", i, r->label_std[i], r->fork_std[i],
                  r->student_rmse.empty() ? 0.0 : r->student_rmse[i]);
    }
    std::vector<int> sorted = r->episode_juggles;
    std::sort(sorted.begin(), sorted.end());
    const double median = sorted.empty() ? 0
                          : sorted.size() % 2 ? sorted[sorted.size() / 2]
                          : 0.5 * (sorted[sorted.size() / 2 - 1] + sorted[sorted.size() / 2]);
    std::printf("states=%d steps=%d juggles=%d median_juggles=%g student_mix=%g "
                "expert_noise=%g noise_hold=%d weighted_spread=%.4f",
                r->states, r->steps, r->juggles, median, f->options.student_mix,
                f->options.expert_noise, f->options.noise_hold_steps, r->weighted_spread);
    if (student) std::printf(" student_weighted_error=%.4f", r->student_weighted_error);
    std::printf("\n");
    for (const bool kicks : {false, true}) {
      const std::string& path = kicks ? f->dump_kicks : f->dump_demos;
      if (path.empty()) continue;
      if (absl::Status s = WriteRows(*r, (*spec)->obs_dim(),
                                     kicks ? r->decision_size : (*spec)->act_dim(),
                                     kicks ? r->row_kicks : r->row_labels, path);
          !s.ok()) {
        return Fail(s);
      }
      std::printf("wrote %d states (%s) to %s\n", r->steps, kicks ? "kick variables" : "actions",
                  path.c_str());
    }
    return 0;
  };
}

}  // namespace juggle

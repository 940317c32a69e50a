// How much the planner's labels vary at one state (docs/planner.md, "Label spread"): a student
// trained on labels can at best predict their mean, so the spread of re-plans of the same
// state with other random streams is the floor of its held-out label error. The driving
// planner juggles; at each of its re-plans `forks` copies of it (same plan, warm start and
// clocks; other streams) plan the same state, and their actions are compared. The spread is
// reported in the units of the imitation loss (learner/imitation_schedule.h): per action the
// squared deviation weighted by 1/max(σ_a², min_label_std²), σ_a the label spread over every
// visited state. With a student and `student_mix` β > 0 the env executes label + β·(student −
// label) instead (β = 1: the student drives, the planner only labels), which measures how much
// of the student's error the juggle tolerates (docs/learning.md). Thread-compatible.
#ifndef JUGGLE_PLANNER_LABEL_SPREAD_H_
#define JUGGLE_PLANNER_LABEL_SPREAD_H_

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "absl/status/statusor.h"
#include "common/config_loader.h"
#include "common/eigen_policy.h"
#include "envs/env.h"

namespace juggle::planner {

struct LabelSpreadOptions {
  int episodes = 4;
  double seconds = 10;   // per episode (simulated)
  int forks = 4;         // re-plans of each state, besides the driving one (0: none)
  uint64_t seed = 1;     // episode starts: streams (seed, 0, episode)
  double min_label_std = 0.08;
  // Optional: a student policy whose mean action is compared with the driving planner's label
  // at every visited state (its label error in the same units).
  const EigenPolicy* student = nullptr;
  // In [0, 1]: the executed action is label + student_mix·(student − label). Needs a student.
  double student_mix = 0;
  // DART (docs/learning.md): Gaussian noise of this std (policy units) added to every executed
  // action (then clamped to [-1, 1]; the label stays the clean action), drawn anew every
  // `noise_hold_steps` control steps (1: independent per step; more: a held offset, like a
  // student's bias). Streams (seed ^ kNoiseSalt, 0, episode) (label_spread.cc).
  double expert_noise = 0;
  int noise_hold_steps = 1;
  // Keep every visited state's observation, label and the kick variables the planner had
  // chosen for the current cycle at its last re-plan (LabelSpreadReport rows).
  bool keep_rows = false;
};

struct LabelSpreadReport {
  int states = 0;       // re-plan states measured
  int steps = 0;        // states visited (labels for σ_a)
  int juggles = 0;      // of the executed actions, over the episodes
  std::vector<int> episode_juggles;
  std::vector<double> label_std;   // σ_a over every visited state's label
  std::vector<double> fork_std;    // per action: RMS over states of the forks' std
  // Mean over states and actions of w_a·s²_a(state), s² the forks' unbiased variance.
  double weighted_spread = 0;
  // With a student: per action the RMS of (student − label) over every visited state, and the
  // mean over states and actions of w_a·(student − label)².
  std::vector<double> student_rmse;
  double student_weighted_error = 0;
  // With keep_rows, per visited state in order: observation [obs_dim], label [act_dim], the
  // current decision's variables [decision_size] (soccer: the 5 kick variables of the current
  // cycle; PlanningTask::decision_size); episode_steps[e] states belong to episode e.
  int decision_size = 0;
  std::vector<float> row_obs, row_labels, row_kicks;
  std::vector<int> episode_steps;
};

// Errors: the planner config check (a family without a planning task among them), forks of 1, a mix out
// of [0, 1] or without a student, negative noise or a hold below 1.
absl::StatusOr<LabelSpreadReport> MeasureLabelSpread(
    std::shared_ptr<const EnvSpec> spec, const LoadedConfig& config,
    const LabelSpreadOptions& options, const std::function<void(const std::string&)>& progress);

}  // namespace juggle::planner

#endif  // JUGGLE_PLANNER_LABEL_SPREAD_H_

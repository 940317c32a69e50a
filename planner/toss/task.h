// The toss family's throw as a planning task (planner/planning_task.h; docs/planner.md, "A second
// task: the toss throw"). It plans the single-arm THROW task (envs/toss/task_env.h): one episode
// is one throw, which ends at the release beat. A plan is the throwing arm's shoulder, elbow and
// wrist actions as a piecewise-linear spline with a knot every `knot_steps` control steps on a
// grid fixed to the episode, in the policy's own action units (with toss.base a residual on the
// base controller's targets, without it the targets themselves), added to the prior action; the
// neck's action is the prior's. A rollout is scored by the release's velocity and position
// errors against the schedule (the env's own measures), the arm's effort (the env's Σ|Δω|) and a
// failure (divergence, or no release inside the horizon). The decision cycle is the throw: the
// episode. Settings: PlannerConfig.toss (proto/planner.proto). Immutable; thread-safe.
#ifndef JUGGLE_PLANNER_TOSS_TASK_H_
#define JUGGLE_PLANNER_TOSS_TASK_H_

#include <memory>
#include <string>
#include <vector>

#include "absl/status/status.h"
#include "common/config_loader.h"
#include "envs/toss/spec.h"
#include "planner/planning_task.h"
#include "proto/planner.pb.h"

namespace juggle::planner {

class TossThrowTask final : public PlanningTask {
 public:
  // The planned joints: shoulder, elbow, wrist (action indices 1..3; 0 is the shared neck).
  static constexpr int kFirstJoint = 1;
  static constexpr int kJoints = 3;

  // REQUIRES: `config` passed ValidateTossTask for a config of `spec`.
  TossThrowTask(std::shared_ptr<const toss::TossSpec> spec, const config::PlannerConfig& config);

  std::string family() const override { return "toss"; }
  const SearchSpace& space() const override { return space_; }
  const SearchSpace& rescue_space() const override { return rescue_space_; }
  int horizon() const override { return horizon_; }
  int KnotAtOrBefore(int step) const override;
  std::vector<double> Shift(const std::vector<double>& theta, int grid_steps,
                            int cycles) const override;
  void Action(const Env& env, const double* theta, PlanClock clock, const double* prior,
              float* action) const override;
  std::unique_ptr<RolloutScorer> NewScorer() const override;
  // release_velocity, release_position, effort, failure.
  std::vector<std::string> term_names() const override;
  // The release's velocity error |v − v̄| (m/s) and position error |p − p̄| (m).
  std::vector<std::string> outcome_names() const override;

  int knots() const { return knots_; }
  const config::TossPlanning& settings() const { return settings_; }

 private:
  std::shared_ptr<const toss::TossSpec> spec_;
  config::TossPlanning settings_;
  int horizon_;
  int knots_;
  SearchSpace space_;
  SearchSpace rescue_space_;  // every spread times PlannerConfig.rescue.sigma_scale, in the box
};

// OK, or INVALID_ARGUMENT "file:line:col: <field>: ..." for a toss run the task cannot plan: a
// task other than THROW (toss.task), the in-loop env (toss.loop: its episodes are segments of a
// two-arm run, not one throw), a horizon that cannot reach the latest release beat
// (planner.horizon_steps against toss.dwell_ratio, hand_period_s and catch_timing_jitter_s) or
// that is longer than the episode (toss.max_episode_steps).
absl::Status ValidateTossTask(const LoadedConfig& config);

}  // namespace juggle::planner

#endif  // JUGGLE_PLANNER_TOSS_TASK_H_

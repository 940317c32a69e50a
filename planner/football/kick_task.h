// Football's kick as a planning task (planner/planning_task.h; docs/football.md, "The kick by
// search"; settings: PlannerConfig.football, proto/planner.proto). One episode of the KICK task
// is one kick. A plan is soccer juggling's layout (planner/soccer_juggle/plan.h) with one kick
// set — the scripted kick's timing, forward hip, abduction, knee and ankle (envs/football/
// kick_motion.h), turned into the feed-forward torques that move the PD target so
// (planner/pose_action.h) — and the whole-body knots of PlannerConfig.body_*. A rollout is scored
// by PhysicsFC's kick deviations over the 1/6-s window after the touch, a miss, a fall and the
// root's tilt at the horizon's end. The kick's times are on the env's kick clock
// (FootballEnv::kick_time_s): TRAP_KICK's kick is this task after the switch (trap_kick_task.h).
// Immutable; thread-safe.
#ifndef JUGGLE_PLANNER_FOOTBALL_KICK_TASK_H_
#define JUGGLE_PLANNER_FOOTBALL_KICK_TASK_H_

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "absl/status/status.h"
#include "common/config_loader.h"
#include "envs/football/spec.h"
#include "planner/planning_task.h"
#include "planner/soccer_juggle/plan.h"
#include "proto/planner.pb.h"

namespace juggle::planner {

class FootballKickTask final : public PlanningTask {
 public:
  // REQUIRES: `config` passed ValidateFootballTask for a config of `spec`.
  FootballKickTask(std::shared_ptr<const football::FootballSpec> spec,
                   const config::PlannerConfig& config);

  std::string family() const override { return "football"; }
  const SearchSpace& space() const override { return space_; }
  const SearchSpace& rescue_space() const override { return rescue_space_; }
  int horizon() const override { return layout_.horizon; }
  int max_run_on_steps() const override;
  int KnotAtOrBefore(int step) const override;
  std::vector<double> Shift(const std::vector<double>& theta, int grid_steps,
                            int cycles) const override;
  void Action(const Env& env, const double* theta, PlanClock clock, const double* prior,
              float* action) const override;
  std::unique_ptr<RolloutScorer> NewScorer() const override;
  // A scorer that begins `first_step` steps into a rollout (TRAP_KICK's kick after the switch).
  std::unique_ptr<RolloutScorer> NewScorerFrom(int first_step) const;
  // direction, speed, miss, failure, upright.
  std::vector<std::string> term_names() const override;
  // The window's KDD (deg), KSD (m/s), mean ball speed (m/s) and the signed errors
  // (football::SignedKickErrors: azimuth and elevation in deg, speed in m/s).
  std::vector<std::string> outcome_names() const override;
  // PlannerConfig.refine_iterations: Levenberg–Marquardt on the kick set while the ball is
  // untouched, over the signed errors weighted as the direction and speed terms.
  std::optional<VariableBlock> RefineBlock(const Env& env) const override;
  int num_residuals() const override { return 3; }
  bool Residuals(const std::vector<double>& outcome, double* residuals) const override;
  const float* AppliedAction(const Env& env) const override;
  int decision_size() const override { return kKickVariables; }
  std::string DescribeDecision(const std::vector<double>& decision,
                               const std::vector<double>& outcome) const override;

  const SoccerPlanLayout& layout() const { return layout_; }

 private:
  std::shared_ptr<const football::FootballSpec> spec_;
  config::FootballPlanning settings_;
  SoccerPlanLayout layout_;
  SearchSpace space_;
  SearchSpace rescue_space_;
};

// OK, or INVALID_ARGUMENT "file:line:col: <field>: ..." for a football run the planner cannot
// plan: a horizon longer than the episode; for KICK and TRAP_KICK, body_actions that name no
// joint, kick variables off.
absl::Status ValidateFootballTask(const LoadedConfig& config);

}  // namespace juggle::planner

#endif  // JUGGLE_PLANNER_FOOTBALL_KICK_TASK_H_

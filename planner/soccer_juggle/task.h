// The soccer juggling planning task (planner/planning_task.h, docs/planner.md): a plan is the
// kick variables of the next juggle cycles and whole-body knots (planner/soccer_juggle/plan.h),
// scored by the kicks' predicted free flights, the body and the effort
// (planner/soccer_juggle/cost.h); a decision cycle starts when a DOWN node is entered; the
// refinement works on the next kick's variables against its timing and landing. Settings:
// PlannerConfig.soccer_juggle and the driver's own fields. Immutable; thread-safe.
#ifndef JUGGLE_PLANNER_SOCCER_JUGGLE_TASK_H_
#define JUGGLE_PLANNER_SOCCER_JUGGLE_TASK_H_

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "absl/status/status.h"
#include "common/config_loader.h"
#include "envs/soccer_juggle/spec.h"
#include "planner/planning_task.h"
#include "planner/soccer_juggle/kick_memory.h"
#include "planner/soccer_juggle/plan.h"
#include "proto/planner.pb.h"

namespace juggle::planner {

class SoccerJuggleTask final : public PlanningTask {
 public:
  // At most this many steps past the horizon to let a kick in contact release the ball.
  static constexpr int kReleaseSteps = 6;

  // REQUIRES: `config` passed ValidateSoccerJuggleTask (its kick memory file reads).
  SoccerJuggleTask(std::shared_ptr<const soccer_juggle::JuggleSpec> spec,
                   const config::PlannerConfig& config);

  std::string family() const override { return "soccer_juggle"; }
  const SearchSpace& space() const override { return space_; }
  const SearchSpace& rescue_space() const override { return rescue_space_; }
  int horizon() const override { return layout_.horizon; }
  int max_run_on_steps() const override { return kReleaseSteps; }
  int KnotAtOrBefore(int step) const override;
  bool StartsCycle(const Env& env, int node) const override;
  std::vector<double> Shift(const std::vector<double>& theta, int grid_steps,
                            int cycles) const override;
  std::vector<std::vector<double>> Seeds(const std::vector<double>& start) const override;
  void Restrict(const Env& env, const std::vector<double>& shifted, SearchSpace* space,
                std::vector<std::vector<double>>* seeds) const override;
  // KickVariables.hold_in_rescue: after the release, before the hold, the rescue holds the
  // follow-through the previous plan (`shifted`) left with.
  bool RestrictRescue(const Env& env, const std::vector<double>& shifted, SearchSpace* space,
                      std::vector<std::vector<double>>* seeds) const override;
  double PlanCost(const double* theta, const std::vector<double>& warm,
                  bool has_warm) const override;
  // The ball's clearance from the bodies its node lets touch it (BallClearance).
  double ContactClearance(const Env& env) const override;
  void Action(const Env& env, const double* theta, PlanClock clock, const double* prior,
              float* action) const override;
  // False while a held follow-through acts (KickVariables.hold_follow_through), without body
  // knots.
  bool PlanActs(const Env& env, const double* theta, PlanClock clock) const override;
  std::unique_ptr<RolloutScorer> NewScorer() const override;
  std::vector<std::string> term_names() const override;
  std::vector<std::string> outcome_names() const override;
  std::optional<VariableBlock> RefineBlock(const Env& env) const override;
  int num_residuals() const override { return 3; }
  bool Residuals(const std::vector<double>& outcome, double* residuals) const override;
  double refine_prior_weight() const override;
  std::optional<VariableBlock> ActingBlock(PlanClock clock) const override;
  const float* AppliedAction(const Env& env) const override;
  int decision_size() const override;
  // "  vars T ms H A K N  kick: timing T ms, landing X Y m, apex A m[, impact I m/s^2]".
  std::string DescribeDecision(const std::vector<double>& decision,
                               const std::vector<double>& outcome) const override;

  const SoccerPlanLayout& layout() const { return layout_; }
  const config::SoccerJugglePlanning& settings() const { return settings_; }

 private:
  // Kick set `set`'s block: 2 ms of timing, 0.01 rad of placement per finite-difference step.
  VariableBlock KickBlock(int set) const;
  // The current cycle's kick has left the foot.
  static bool Released(const Env& env);
  // While the ball flies to the next contact: the first seed with the next kick's set replaced by
  // each of the kick memory's nearest decisions, appended to `seeds`.
  void AddRememberedKicks(const Env& env, std::vector<std::vector<double>>* seeds) const;
  // KickVariables.hold_follow_through: the held kick and its flag fixed in `space` and every
  // seed for `env`'s state.
  void HoldFollowThrough(const Env& env, const std::vector<double>& shifted, SearchSpace* space,
                         std::vector<std::vector<double>>* seeds) const;
  // Fixes the held kick and its count to `held` (kKickVariables + 1 values) in `space` and
  // every seed.
  void FixHeld(const double* held, SearchSpace* space,
               std::vector<std::vector<double>>* seeds) const;

  std::shared_ptr<const soccer_juggle::JuggleSpec> spec_;
  config::SoccerJugglePlanning settings_;
  bool run_on_every_kick_;
  SoccerPlanLayout layout_;
  SearchSpace space_;
  SearchSpace rescue_space_;  // PlannerConfig.rescue's: every spread widened, body knots free
  std::optional<KickMemory> memory_;  // SoccerJugglePlanning.kick_memory
};

// OK, or INVALID_ARGUMENT "file:line:col: planner.<field>: ..." for soccer settings the schema's
// ranges allow but the run does not: a horizon longer than the episode, a body action that names
// no joint, an empty impact band, a kick memory file that does not read.
absl::Status ValidateSoccerJuggleTask(const LoadedConfig& config);

}  // namespace juggle::planner

#endif  // JUGGLE_PLANNER_SOCCER_JUGGLE_TASK_H_

// Football's trap then kick as a planning task (planner/planning_task.h; docs/football.md,
// "Trap then kick"): the TRAP_KICK env's state machine planned whole. A plan is the trap's reach
// pose (trap_task.h, kTrapVariables) followed by the kick's variables (kick_task.h); before the
// env's switch to the kick the trap's part acts, after it the kick's. A rollout is scored by the
// trap's terms until the switch (at the switch's state), with a `zone` term for a trapped ball
// whose free path does not come to rest in the kick's zone (envs/football/trap_kick.h) and
// `out_of_reach` when the env says so, and by the kick's terms from the switch on (each named
// kick_*). After the switch the trap's variables are held. A part's own trap settings
// (TrapPlanning.foot, ...) act as in TRAP: its space, its pose, its weights. With
// FootballPlanning.second_touch the plan has a second decision between the two
// (kSecondTouchVariables): a reach of the right leg complete a searched time after the trap's
// touch, added to the trap's pose — a stop or a tap that steers the bounced ball into the
// zone. It is a decision of its own: until the first touch only the trap's reach is searched
// (the second touch held at no change, acting nothing), from the touch on only the second
// touch (the reach held). Immutable; thread-safe.
#ifndef JUGGLE_PLANNER_FOOTBALL_TRAP_KICK_TASK_H_
#define JUGGLE_PLANNER_FOOTBALL_TRAP_KICK_TASK_H_

#include <memory>
#include <string>
#include <vector>

#include "envs/football/spec.h"
#include "planner/football/kick_task.h"
#include "planner/football/trap_task.h"
#include "planner/planning_task.h"
#include "proto/planner.pb.h"

namespace juggle::planner {

// How far (m) the free path of the ball in `env` comes to the kick's zone (0: it passes
// through the zone slower than trap_kick.max_speed_mps): over its path on the turf until the
// env's wait for the switch ends, the least of the ground-plane distance to the zone plus
// 0.5 s × the speed beyond the limit. REQUIRES: a TRAP_KICK env.
double FreePathZoneDistance(const Env& env);

// The second touch's variables: when the reach is complete after the touch (s), right hip
// flexion, right hip abduction, right knee bend, right ankle pitch (rad), give (0–1).
constexpr int kSecondTouchVariables = 6;

class FootballTrapKickTask final : public PlanningTask {
 public:
  // REQUIRES: `config` passed ValidateFootballTask for a TRAP_KICK config of `spec`.
  FootballTrapKickTask(std::shared_ptr<const football::FootballSpec> spec,
                       const config::PlannerConfig& config);

  std::string family() const override { return "football"; }
  const SearchSpace& space() const override { return space_; }
  const SearchSpace& rescue_space() const override { return rescue_space_; }
  // The rescue space with the trap's variables in the pass's part's space (TrapPlanningFor).
  SearchSpace RescueSpaceAt(const Env& env) const override;
  int horizon() const override { return horizon_; }
  int max_run_on_steps() const override;
  // The kick's decision grid (its body knots, when set).
  int KnotAtOrBefore(int step) const override;
  std::vector<double> Shift(const std::vector<double>& theta, int grid_steps,
                            int cycles) const override;
  void Restrict(const Env& env, const std::vector<double>& shifted, SearchSpace* space,
                std::vector<std::vector<double>>* seeds) const override;
  void Action(const Env& env, const double* theta, PlanClock clock, const double* prior,
              float* action) const override;
  std::unique_ptr<RolloutScorer> NewScorer() const override;
  // The trap's terms, then zone, out_of_reach, then the kick's as kick_<name>.
  std::vector<std::string> term_names() const override;
  const float* AppliedAction(const Env& env) const override;
  int decision_size() const override { return dim(); }
  std::string DescribeDecision(const std::vector<double>& decision,
                               const std::vector<double>& outcome) const override;

 private:
  std::shared_ptr<const football::FootballSpec> spec_;
  int horizon_;
  FootballTrapTask trap_;
  FootballKickTask kick_;
  int second_;  // kSecondTouchVariables with the second touch, else 0
  SearchSpace space_, rescue_space_;

  int kick_offset() const { return kTrapVariables + second_; }
  // `space` with the trap's variables in the space of `env`'s pass's part.
  SearchSpace WithPartSpace(const Env& env, SearchSpace space) const;
  // The second touch's leg change now (none when off or before its ramp).
  LegChange SecondTouchChange(const Env& env, const double* theta) const;
};

}  // namespace juggle::planner

#endif  // JUGGLE_PLANNER_FOOTBALL_TRAP_KICK_TASK_H_

// Football's trap as a planning task (planner/planning_task.h; docs/football.md, "The trap by
// search"; settings: FootballPlanning.trap, proto/planner.proto). One episode of the TRAP task
// is one trap. A plan is one reach pose around the pass's meeting time — changes of the
// standing pose's right hip (flexion, abduction), right knee (bend; both knees in a squat for a
// part with TrapPlanning.squat), right ankle (pitch), the trunk's lean (both hips' flexion),
// chest and neck (pitch), reached with a smoothstep over
// `ramp_s` that ends `timing` s after the meeting time, then partly taken back (the give, a
// cushion) — turned into the feed-forward torques that make that change of the PD
// target (planner/pose_action.h), so a plan is an action sequence a policy could produce. A
// rollout is scored by the designated part's closest approach to the ball's path before the
// touch, the ball's speed relative to the root after it (seed 002's RBSPT) and where its free
// path leaves it at the trap's end against the reach, another part or the turf first, the arms, a
// fall and the root's tilt. Immutable; thread-safe.
#ifndef JUGGLE_PLANNER_FOOTBALL_TRAP_TASK_H_
#define JUGGLE_PLANNER_FOOTBALL_TRAP_TASK_H_

#include <array>
#include <memory>
#include <string>
#include <vector>

#include "common/config_loader.h"
#include "envs/football/spec.h"
#include "planner/planning_task.h"
#include "proto/planner.pb.h"

namespace juggle::planner {

// timing (s), right hip flexion, right hip abduction, right knee bend, right ankle pitch, trunk
// lean (both hips' flexion), chest pitch, neck pitch (rad), give (the share of the changes taken
// back after the reach, in [0, 1]: a cushion).
constexpr int kTrapVariables = 9;

// Changes of the right leg's joints (rad) added to a reach pose: hip flexion, hip abduction,
// knee bend, ankle pitch (trap_kick_task.h's second touch).
struct LegChange {
  double hip = 0, abduction = 0, knee = 0, ankle = 0;
};

// How a reach rises to its pose and is given back after it (s).
struct ReachRamps {
  double rise_s, give_s;
};

// TrapPlanning's ramps: ramp_s, and give_ramp_s where set (else ramp_s).
ReachRamps ReachRampsOf(const config::TrapPlanning& p);

// `p` with the settings for passes designated to `part` (TrapPlanning.foot, .lower_leg, .torso,
// .head) over it, for a ground pass TrapPlanning.ground's over those, and no part settings of
// its own.
config::TrapPlanning TrapPlanningFor(const config::TrapPlanning& p, config::TrapPart part,
                                     bool ground_pass = false);

// The reach pose of plan `theta` (kTrapVariables values) at episode time `t` for a pass that
// meets its point at `meet_s`: the standing pose plus w × the changes, w rising as
// smoothstep((t − (reach − rise_s)) / rise_s) up to reach = meet_s + timing, then falling as
// 1 − give × smoothstep((t − reach) / give_s) (below 0 for a give above 1: past the standing
// pose, away from the reach); `extra` added to the right leg's. With `squat` the knee variable
// bends both knees, and flexes both hips and both ankles (toes up) by half of it
// (TrapPlanning.squat).
void TrapReachPose(const football::FootballSpec& spec, const double* theta, double meet_s, double t,
                   const ReachRamps& ramps, humanoid::CharacterPose* pose,
                   const LegChange& extra = {}, bool squat = false);

// The weight of a reach complete at `reached` that rises and gives back by `ramps`, at `t`.
double ReachWeight(double reached, double give, double t, const ReachRamps& ramps);

// A reach's search space: its timing in [earliest_s, latest_s], `angles` joint changes within
// ±angle_limit, then its give in [0, give_max].
SearchSpace ReachSpace(double earliest_s, double latest_s, double timing_sigma_s, int angles,
                       double angle_limit, double angle_sigma, double give_max = 1);

class FootballTrapTask final : public PlanningTask {
 public:
  // REQUIRES: `config` passed ValidateFootballTask for a TRAP (or TRAP_KICK) config of `spec`.
  FootballTrapTask(std::shared_ptr<const football::FootballSpec> spec,
                   const config::PlannerConfig& config);

  std::string family() const override { return "football"; }
  // The space of passes without part settings; Restrict and RescueSpaceAt give the pass's part's.
  const SearchSpace& space() const override { return part_space_[config::TRAP_PART_UNSPECIFIED]; }
  const SearchSpace& rescue_space() const override { return space(); }
  SearchSpace RescueSpaceAt(const Env& env) const override;
  void Restrict(const Env& env, const std::vector<double>& shifted, SearchSpace* space,
                std::vector<std::vector<double>>* seeds) const override;
  int horizon() const override { return horizon_; }
  int max_run_on_steps() const override;
  std::vector<double> Shift(const std::vector<double>& theta, int grid_steps,
                            int cycles) const override {
    return theta;  // one reach per episode, on the episode's clock
  }
  void Action(const Env& env, const double* theta, PlanClock clock, const double* prior,
              float* action) const override;
  // Action with `extra` added to the right leg's changes.
  void ActionWithLeg(const Env& env, const double* theta, const LegChange& extra,
                     const double* prior, float* action) const;
  std::unique_ptr<RolloutScorer> NewScorer() const override;
  // reach, relative_speed, keep (the ball beyond trap.reach_m − keep_margin_m at the trap's end),
  // miss, handball, failure, upright.
  std::vector<std::string> term_names() const override;
  // The designated part's touch: the mean relative speed over the frames recorded (m/s).
  std::vector<std::string> outcome_names() const override;
  const float* AppliedAction(const Env& env) const override;
  int decision_size() const override { return kTrapVariables; }
  std::string DescribeDecision(const std::vector<double>& decision,
                               const std::vector<double>& outcome) const override;

  // The trap's settings for passes designated to `part` (TrapPlanningFor).
  const config::TrapPlanning& Planning(config::TrapPart part) const { return by_part_[part]; }
  // The trap's settings for `episode`'s pass: its part's, or the ground passes'.
  const config::TrapPlanning& PlanningFor(const football::TrapEpisode& episode) const;
  // The reach's search space for `env`'s pass: its part's, or the ground passes'.
  const SearchSpace& PartSpace(const Env& env) const;

 private:
  std::shared_ptr<const football::FootballSpec> spec_;
  config::FootballPlanning settings_;
  int horizon_;
  // By TrapPart number (0: the settings without a part's).
  std::array<config::TrapPlanning, config::TrapPart_ARRAYSIZE> by_part_;
  std::array<SearchSpace, config::TrapPart_ARRAYSIZE> part_space_;
  config::TrapPlanning ground_;  // ground passes' (they go to the foot)
  SearchSpace ground_space_;
};

}  // namespace juggle::planner

#endif  // JUGGLE_PLANNER_FOOTBALL_TRAP_TASK_H_

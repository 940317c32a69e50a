// The soccer juggling task's decision variables and the actions they give (docs/planner.md).
//
// A plan θ is, in order:
//   kick variables, one set per juggle cycle (KickVariables.cycles sets; a cycle starts when a
//   DOWN node is entered): the contact node's timing (s earlier), and for a leg swing its hip
//   flexion, hip abduction, knee and ankle-pitch amplitudes (rad), for the other generators
//   (head, chest) the chest's pitch, the neck's pitch, the chest's and the neck's roll (the
//   sideways lean that steers a header across) and both knees' bend (rad, largest at the
//   contact);
//   whole-body knots: body_knots × 28 actions (policy units), a piecewise-linear spline with a
//   knot every knot_steps control steps of the episode, on a grid fixed to the episode (knot 0
//   of a plan is the grid knot at or before its origin), so a re-plan keeps the knots it
//   shares with the previous plan where they were and the shifted plan acts exactly as before.
//   with KickVariables.hold_follow_through, the held kick: kKickVariables values the current
//   cycle's follow-through uses instead of its set, and a count (0: the kick had not left
//   before the plan; k: the plan is the k-th re-plan since it left, holding once k passes
//   KickVariables.hold_after_replans), never searched (the task sets both at each re-plan).
// At a visited state the plan's action is the kick variables' change of the PD target turned
// into the feed-forward torque it makes (kp × the target's change, per joint and axis, divided
// by the action's torque unit; in a STALL node, whose phase is held, the angles move the held
// pose and the timing nothing) plus the spline's value, clamped to [−1, 1]: a plan is an action
// sequence the learned policy could produce, so its labels are exact. Pure functions;
// allocation-free.
#ifndef JUGGLE_PLANNER_SOCCER_JUGGLE_PLAN_H_
#define JUGGLE_PLANNER_SOCCER_JUGGLE_PLAN_H_

#include <algorithm>
#include <string>
#include <vector>

#include "absl/status/statusor.h"

#include "envs/soccer_juggle/env.h"
#include "envs/soccer_juggle/spec.h"
#include "planner/cem_search.h"
#include "planner/planning_task.h"
#include "proto/planner.pb.h"

namespace juggle::planner {

constexpr int kKickVariables = 5;  // timing (s), hip, abduction, knee, ankle (rad)

// The finite-difference steps of a kick set's refinement (VariableBlock.steps), in the order
// above: soccer juggling's and football's kicks share them.
inline std::vector<double> KickRefineSteps() { return {0.002, 0.01, 0.01, 0.01, 0.01}; }

struct SoccerPlanLayout {
  int kick_sets = 0;     // 0 when KickVariables.enabled is false
  // Cycles past the last set kick with no variables (KickVariables.later_kicks_by_base).
  bool later_kicks_by_base = false;
  bool hold_follow_through = false;  // KickVariables.hold_follow_through
  int hold_after = 0;                // KickVariables.hold_after_replans
  bool hold_in_rescue = false;       // KickVariables.hold_in_rescue
  double act_from_phase = 0;         // KickVariables.act_from_phase (0: no ramp)
  int knot_steps = 0;    // 0: no whole-body corrections
  int body_knots = 0;    // enough to span a horizon from anywhere between two grid knots
  int horizon = 1;
  std::vector<int> body_actions;  // the action indices a knot holds, in order
  int knot_size() const { return static_cast<int>(body_actions.size()); }
  int kick_dim() const { return kick_sets * kKickVariables; }
  int held_dim() const { return hold_follow_through ? kKickVariables + 1 : 0; }
  int dim() const { return kick_dim() + body_knots * knot_size() + held_dim(); }
  // Index of the held kick's first value and of its count (hold_follow_through only).
  int held() const { return kick_dim() + body_knots * knot_size(); }
  int held_count() const { return held() + kKickVariables; }
  // Whether a plan's cycle `cycle` acts through the held kick (the follow-through of a kick that
  // left before the plan, once held).
  bool follows_held(const double* theta, int cycle) const {
    return hold_follow_through && cycle == 0 && theta[held_count()] > hold_after;
  }
  // Index of the first variable of kick set `set` / body knot `knot`.
  int kick(int set) const { return set * kKickVariables; }
  // The kick set that acts in plan cycle `cycle` (the last set for cycles past it), or -1: none
  // (no kick variables, or a later cycle kicked by the base controller).
  int acting_kick_set(int cycle) const {
    if (kick_sets == 0 || (later_kicks_by_base && cycle >= kick_sets)) return -1;
    return std::clamp(cycle, 0, kick_sets - 1);
  }
  int knot(int k) const { return kick_dim() + k * knot_size(); }
  // The share of a kick set's moves that acts at cycle phase `phase` (KickVariables.
  // act_from_phase): 0 before act_from_phase, sin²(π/2 · u) up to the contact (0.5), 1 from
  // there; exactly 1 everywhere without a ramp.
  double kick_ramp(double phase) const;
};

// The action indices named by PlannerConfig.body_actions (all 28 when empty), or
// INVALID_ARGUMENT naming the entry that is not a joint or axis of the character.
absl::StatusOr<std::vector<int>> BodyActionIndices(
    const google::protobuf::RepeatedPtrField<std::string>& names);

// REQUIRES: config.body_actions valid (BodyActionIndices).
// `kick`: the task's kick variables (SoccerJugglePlanning.kick).
SoccerPlanLayout MakeSoccerPlanLayout(const config::PlannerConfig& config,
                                      const config::KickVariables& kick);
// The box and spreads of the variables.
SearchSpace MakeSoccerSearchSpace(const SoccerPlanLayout& layout,
                                  const config::PlannerConfig& config,
                                  const config::KickVariables& kick);

// Value of body action `i` (an index into layout.body_actions) of the body spline `step` control
// steps after knot 0 (the last knot held past the end). REQUIRES: layout.body_knots > 0.
double BodySplineValue(const SoccerPlanLayout& layout, const double* theta, int step, int i);

// "  vars +12 ms +0.10 -0.02 +0.00 +0.05" (timing in ms, then the four angles in rad) for a
// decision of kKickVariables values; empty otherwise (--planner-trace lines).
std::string FormatKickVariables(const std::vector<double>& decision);

// The grid knot at or before episode step `step` (its episode step).
int KnotAtOrBefore(const SoccerPlanLayout& layout, int step);

// The plan's action in `env`'s current state (PlanClock: planner/planning_task.h, the cycles
// being juggle cycles): `prior` (kNumActions values, or null for zero) plus the plan's offsets,
// clamped to [−1, 1]. REQUIRES: theta holds layout.dim() values, `action` kNumActions floats.
void SoccerPlanAction(const soccer_juggle::JuggleEnv& env, const SoccerPlanLayout& layout,
                      const double* theta, PlanClock clock, float* action,
                      const double* prior = nullptr);

// The plan re-expressed from later: body knots moved down by `knots` grid knots (knots past
// the old last copy it), kick sets moved down by `cycles` (likewise). The shifted plan gives
// the same actions at every state the old one reached before its last knot.
std::vector<double> ShiftSoccerPlan(const SoccerPlanLayout& layout, const std::vector<double>& theta,
                                    int knots, int cycles);

}  // namespace juggle::planner

#endif  // JUGGLE_PLANNER_SOCCER_JUGGLE_PLAN_H_

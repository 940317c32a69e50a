// One football environment. Task KICK: the humanoid stands on the pitch with a ball at rest or
// rolling slowly in front of its right foot and a target velocity for the ball; the PD tracks
// the scripted kick (kick_motion.h) plus the action's feed-forward torques and, during the
// kick, the stance balance over the left foot (envs/humanoid/stance_balance.h). Task TRAP: a
// pass comes in (trap_episode.h) for a designated part; the PD holds the standing pose plus the
// actions (with the stance balance throughout for the foot and the lower leg); the episode
// ends settle_s after the first touch (trapped), at the turf first (ground_first), another part
// first (wrong_part), a fall or the step limit. Task TRAP_KICK (seed 002's state machine for the
// two): the trap as TRAP (standing pose plus actions) until, after the designated part's touch,
// the ball lies in the kick's zone (trap_kick.h); then the kick as KICK on a clock that starts
// there (kick_time_s), at a target drawn at the reset; it ends as KICK does, or as a failed
// trap, or out_of_reach. With the stance balance set it stands on both feet
// (AddDoubleStanceBalance) but during the kick, which stands on the left.
//
// Control step = `substeps` physics steps. Per substep: stable PD + feed-forward, mj_step, the
// divergence check, the first touch of the ball by the character (the kicking foot, or another
// body: the episode ends as wrong_touch). After each control step within 1/6 s of the touch the
// ball's velocity is sampled for PhysicsFC's kick metrics (metrics.h); the episode ends
// `settle_s` after the touch (kicked), at a fall, or at the step limit.
// Thread-compatible: one thread at a time.
#ifndef JUGGLE_ENVS_FOOTBALL_ENV_H_
#define JUGGLE_ENVS_FOOTBALL_ENV_H_

#include <array>
#include <memory>
#include <vector>

#include "envs/env.h"
#include "envs/football/metrics.h"
#include "envs/football/spec.h"

namespace juggle::football {

// PhysicsFC's kick measuring window after the touch (s).
constexpr double kKickWindowS = 1.0 / 6.0;

// The episode's own variables beside the physics. Copyable: a snapshot is this plus the
// physics.
struct FootballEnvState {
  Rng rng{0};
  int steps = 0;
  CharacterPose reference{};       // the PD target of the last step
  KickAttempt kick;                // target, touch and the velocity samples after it
  double touch_time_s = -1;        // simulated time of the first touch (−1: none yet)
  int touch_body = -1;             // the body that touched the ball first
  double touch_foot_speed = 0;     // the kicking foot's speed at the touch (m/s)
  bool window_done = false;        // 1/6 s has passed since the touch
  KickScore score;                 // valid once window_done
  bool fell = false;
  std::array<float, kNumActions> previous_action{};
  TrapEpisode trap;                // TRAP, TRAP_KICK
  // Episode time (s) at which the kick's clock starts: 0 for KICK; −1 for TRAP, and for
  // TRAP_KICK until the switch from the trap.
  double kick_origin_s = 0;
  // The kick's first touch counts only once the ball has been free of the character since the
  // switch (a trapped ball may rest against the foot; the back-swing frees it). KICK: true.
  bool touch_armed = true;
};

class FootballSnapshot final : public EnvSnapshot {
 public:
  std::string family() const override { return "football"; }
  FootballEnvState state;
};

class FootballEnv : public juggle::Env {
 public:
  FootballEnv(std::shared_ptr<const FootballSpec> spec, Rng rng);
  FootballEnv(const FootballEnv&) = delete;
  FootballEnv& operator=(const FootballEnv&) = delete;

  // Draws the ball's start and the kick's target (KickTargets) and stands the character.
  void Reset(const AdaptiveWalk& walk) override;
  StepResult Step(const float* action, const AdaptiveWalk& walk) override;
  void WriteObservation(float* obs) const override;
  int steps() const override { return s_.steps; }
  // 1 once the kick's window has been measured as a success (KICK), the trap has settled as one
  // (TRAP), or the sequence has succeeded (TRAP_KICK: trap_kick_success) (metrics.h), else 0.
  int completions() const override;
  mjData* data() override { return data_.get(); }
  const mjData* data() const override { return data_.get(); }
  // TRAP: trap_success (0/1: the designated part first, before the turf, the ball within reach
  // settle_s later), trap_touch_before_ground (0/1: any part first, before the turf: seed 002's
  // own success), trap_handball (a success the arms touched), trap_arms_touched (0/1, any
  // attempt: HRTS under seed 002's own success), trap_rbspt_mps (the relative speed over 5
  // frames after the first touch, once measured; RBSPT averages successes only), trap_part
  // (config::TrapPart), trap_lob (0/1), trap_meet_speed_mps, trap_end_distance_m, fell.
  // KICK: kick_success (0/1), and for a success kick_direction_deviation_deg and
  // kick_speed_deviation_mps; kick_target_speed_mps; kick_speed_mps (the mean measured speed);
  // kick_foot_speed_mps (the kicking foot's speed at the touch), kick_touch_s (when); once
  // anything touched the ball, which part did first, as 0/1 (all 0: the kicking foot; else the
  // kick ends as wrong_touch): kick_touch_kicking_leg (its lower leg or thigh),
  // kick_touch_standing_leg (the standing foot, lower leg or thigh), kick_touch_upper_body (the
  // trunk, head or an arm); fell (0/1).
  // TRAP_KICK: TRAP's; trap_kick_switched (0/1: the ball came into the kick's zone) and
  // trap_kick_switch_s (when); once switched, KICK's; trap_kick_success (0/1: switched, the
  // kick a success, no fall).
  void AppendEpisodeMetrics(std::vector<NamedValue>* out) const override;
  std::unique_ptr<EnvSnapshot> Snapshot() const override;
  absl::Status Restore(const EnvSnapshot& snapshot) override;

  const FootballSpec& spec() const { return *spec_; }
  const FootballEnvState& state() const { return s_; }
  // Simulated seconds since the episode's start.
  double time_s() const { return s_.steps * spec_->control_dt(); }
  // Whether the kick is under way (KICK always; TRAP_KICK after the switch).
  bool kicking() const { return s_.kick_origin_s >= 0; }
  // Seconds on the kick's clock (the scripted kick's times, kick_motion.h). REQUIRES: kicking().
  double kick_time_s() const { return time_s() - s_.kick_origin_s; }
  // The ball's velocity the target asks for (m/s, world frame).
  void TargetVelocity(double v[3]) const;

 private:
  // football.reference_feedforward: the kick's inverse dynamics at episode time `t`, clamped.
  void AddReferenceFeedforward(double t, double* feedforward);
  void NoteTouches();
  void ResetKick();
  // Draws the kick's target speed and direction (KickTargets).
  void DrawKickTarget();
  // After a control step of the TRAP task: its bookkeeping and outcome.
  void AfterTrapStep(StepResult* result);
  // After a control step of TRAP_KICK's trap phase: TRAP's bookkeeping, its failures, the
  // switch to the kick and out_of_reach.
  void AfterTrapKickTrapStep(StepResult* result);
  // After a control step of the kick (KICK, or TRAP_KICK after the switch).
  void AfterKickStep(bool touched_before, StepResult* result);
  // TRAP_KICK without a switch: where the ball is at the end against the kicking foot's
  // standing centre (ahead, across: + left), its height above resting, its horizontal speed
  // and its distance from the kick's zone.
  void AppendUnkickedBall(std::vector<NamedValue>* out) const;
  void AppendKickMetrics(std::vector<NamedValue>* out) const;
  void AppendTrapMetrics(std::vector<NamedValue>* out) const;
  bool Diverged() const;
  bool Fallen() const;

  std::shared_ptr<const FootballSpec> spec_;
  const mjModel* model_;
  MjDataPtr data_;
  MjDataPtr id_data_;  // scratch of the reference feed-forward; null when it is off
  FootballEnvState s_;
};

// `env` as the football env it is (REQUIRES: a FootballEnv, e.g. a football planning task's).
inline const FootballEnv& AsFootballEnv(const Env& env) {
  return static_cast<const FootballEnv&>(env);
}

}  // namespace juggle::football

#endif  // JUGGLE_ENVS_FOOTBALL_ENV_H_

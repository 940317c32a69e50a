// TossTaskEnv: the seed-001 single-arm training tasks on a TossWorld, selected by toss.task.
//
// CATCH: the hand starts near home (start noise) just after a release; one incoming ball,
//   thrown by the schedule (Eq. 1–3) with a value in [min_throw, max_throw] from the other hand
//   (odd) or this one (even), lands at hand_z near the home point (± landing_spread, flight
//   time ± flight_jitter), arriving arrival_min_s..arrival_max_s after the start.
//   Reward per step: −w1·effort. Ends on a catch (+w2·(−min(|z̄ − z|, 1)), z̄ = hand_z; outcome
//   kCaught, one completion) or when the ball falls below drop_z (−w2; kDropped).
// THROW: the hand holds a just-caught ball near home; the release beat comes after
//   t_throw = D_ratio·P_hand ± catch_timing_jitter_s. Reward per step −w3·effort; at the release
//   (kReleased) −w4·|p̄ − p|² − w5·|v̄ − v|² with p̄ the home point and v̄ Eq. 2–3's velocity.
//   The throw counts as a completion if the ball would come down at hand_z within
//   2·catch_radius of the catching hand's home point and within 0.1 s of the schedule.
// Observations are the arm's S_catch (+ t_throw, v̄ for THROW) in the right arm's frame; the env
// runs the right arm unless built for the left (tests of mirroring). The other arm holds home.
#ifndef JUGGLE_ENVS_TOSS_TASK_ENV_H_
#define JUGGLE_ENVS_TOSS_TASK_ENV_H_

#include <memory>
#include <optional>
#include <vector>

#include "common/rng.h"
#include "envs/env.h"
#include "envs/toss/base_controller.h"
#include "envs/toss/world.h"

namespace juggle::toss {

// The task env's own variables of an episode (the world's are in TossWorld::Snapshot).
struct TossTaskState {
  Rng rng{0};
  Hand hand = Hand::kRight;
  double mirror = 1;
  int steps = 0;
  int completions = 0;
  // THROW task.
  int throw_value = 0;
  int release_step = 0;
  bool released = false;  // this episode ended in a release
  Vec2 target_velocity;
  double release_velocity_error = 0, release_position_error = 0;
};

class TossTaskSnapshot final : public EnvSnapshot {
 public:
  std::string family() const override { return "toss"; }
  TossWorld::Snapshot world;
  TossTaskState state;
};

class TossTaskEnv : public juggle::Env {
 public:
  TossTaskEnv(std::shared_ptr<const TossSpec> spec, Rng rng, Hand hand = Hand::kRight);

  void Reset(const AdaptiveWalk& walk) override;
  StepResult Step(const float* action, const AdaptiveWalk& walk) override;
  void WriteObservation(float* obs) const override;
  int steps() const override { return s_.steps; }
  int completions() const override { return s_.completions; }
  mjData* data() override { return world_.data(); }
  const mjData* data() const override { return world_.data(); }
  // THROW: release_position_error and release_velocity_error of the episode's release.
  void AppendEpisodeMetrics(std::vector<NamedValue>* out) const override;
  // The episode's exact state; Restore continues it bit for bit (envs/env_snapshot.h). A
  // snapshot of the in-loop env (TossLoopEnv) is refused.
  std::unique_ptr<EnvSnapshot> Snapshot() const override;
  absl::Status Restore(const EnvSnapshot& snapshot) override;

  const TossWorld& world() const { return world_; }
  // THROW: the throw value asked for, the desired release velocity (world frame) and the last
  // release's velocity error |v̄ − v| and position error |p̄ − p| (m/s, m).
  int throw_value() const { return s_.throw_value; }
  Vec2 target_velocity() const { return s_.target_velocity; }
  double release_velocity_error() const { return s_.release_velocity_error; }
  double release_position_error() const { return s_.release_position_error; }

 private:
  // The acting arm from one of the config's recorded start states, perturbed.
  void StartFromRecordedState();
  void ResetCatch();
  void ResetThrow();
  int SampleThrowValue();
  StepResult StepCatch();
  StepResult StepThrow();

  std::shared_ptr<const TossSpec> spec_;
  TossWorld world_;
  TossTaskState s_;
  // With toss.base: the acting arm's action is a residual on these, the other arm runs them.
  std::optional<TossBaseController> base_;
};

}  // namespace juggle::toss

#endif  // JUGGLE_ENVS_TOSS_TASK_ENV_H_

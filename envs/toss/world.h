// TossWorld: the planar upper body and its balls in MuJoCo, with what the seed-001 paper does
// outside the physics: PD control of both arms to target angles (τ = kp·(θ̄ − θ − h·ω), kd as
// implicit joint damping), balls that ignore each other, automatic catch (a free, descending
// ball within catch_radius of an empty palm may be attached) and release (a held ball leaves
// with the palm's velocity), parked balls kept out of the way, and wind on balls in flight.
// Used by the training tasks (TossTaskEnv) and the two-arm runtime (TossJuggler).
// Policies see the world in the right arm's frame: WriteArmObservation mirrors the left arm.
// Thread-compatible.
#ifndef JUGGLE_ENVS_TOSS_WORLD_H_
#define JUGGLE_ENVS_TOSS_WORLD_H_

#include <array>
#include <memory>
#include <optional>

#include <mujoco/mujoco.h>

#include "common/rng.h"
#include "envs/env_snapshot.h"
#include "envs/mujoco_model.h"
#include "envs/toss/spec.h"

namespace juggle::toss {

struct Vec2 {
  double x = 0, z = 0;
};

enum class BallMode { kParked, kFree, kHeld };

// One arm's joint angles (rad) and speeds (rad/s) in the right arm's frame, 𝒥 order.
struct TossArmState {
  std::array<double, kTossJoints> angle{}, speed{};
};

class TossWorld {
 private:
  struct BallState {
    BallMode mode = BallMode::kParked;
    Hand holder = Hand::kRight;
  };

 public:
  // Everything of the world that the next Step reads (envs/env_snapshot.h).
  struct Snapshot {
    PhysicsSnapshot physics;
    std::array<BallState, kTossBalls> balls{};
    std::array<std::array<double, kTossJoints>, 2> target{};
    std::array<std::array<double, kTossJoints>, 2> prev_speed{};
    std::array<Vec2, kTossBalls> prev_ball{};
    std::array<Vec2, 2> prev_palm{};
    bool diverged = false;
  };
  void Save(Snapshot* out) const;
  // REQUIRES: `s` was saved from a world of an equal spec.
  void Restore(const Snapshot& s);

  explicit TossWorld(std::shared_ptr<const TossSpec> spec);
  // An exact copy (Save and Restore): it steps bit for bit as `other` would.
  TossWorld(const TossWorld& other);
  TossWorld& operator=(const TossWorld&) = delete;

  // Time 0, every ball parked, both arms at home (targets too). With `rng`, the shoulder, elbow
  // and wrist angles get home ± angle_noise (rad) and speeds ± speed_noise (rad/s), one draw
  // applied to both arms as mirror images (the neck stays centred); without, exactly at home
  // and at rest.
  void Reset(Rng* rng, double angle_noise, double speed_noise);

  // `hand`'s arm state, mirrored into the right arm's frame (the neck included).
  TossArmState ArmState(Hand hand) const;
  // Puts `hand`'s arm (and the shared neck) in `state` (right arm's frame), recomputes the
  // kinematics and restarts the effort's speed history there. Held balls are not moved.
  void SetArmState(Hand hand, const TossArmState& state);

  void SetFree(int ball, Vec2 position, Vec2 velocity);
  // Attaches `ball` to `hand`'s palm (from the next Step on it moves with the palm).
  void Hold(int ball, Hand hand);
  // Releases a held ball with the palm's current position and velocity; returns the velocity.
  Vec2 Release(int ball);
  void Park(int ball);

  // Targets of `hand`'s arm from a policy action in the right arm's frame:
  // θ̄ = mirror · (home + action_scale · clamp(action, −1, 1)). The neck follows the mean of
  // both arms' neck targets.
  void SetAction(Hand hand, const float* action);
  void SetHomeTargets(Hand hand);
  // World-frame target angles of `hand`'s arm, 𝒥 order (the base controllers' output,
  // envs/toss/base_controller.h).
  void SetTargets(Hand hand, const std::array<double, kTossJoints>& targets);

  // Wind on free balls from now on (N along x), instead of the config's wind_force (the live
  // page's wind).
  void set_wind(double newtons) { wind_override_ = newtons; }
  double wind() const;

  // One 10 ms step: PD torques, held balls' weight on the palms, wind on free balls, mj_step,
  // then held balls follow their palms and parked balls are put back. Sets diverged() on a
  // MuJoCo warning or a non-finite state.
  void Step();

  // A free, descending ball that came within catch_radius of `hand`'s palm (x–z distance)
  // during the last Step, the hand empty. The ball's path relative to the palm is taken as a
  // straight segment between the steps, so a fast ball cannot pass the palm between two checks.
  bool CanCatch(int ball, Hand hand) const;

  // Σ_j |ω_j,t − ω_j,t−1| over `hand`'s 𝒥 joints in the last Step (the paper's effort).
  double Effort(Hand hand) const;
  // S_catch of `hand` about `ball` (ball < 0: none; the palm's own state is written) in the right
  // arm's frame, positions relative to the home point: p_hand, ṗ_hand, p_ball, ṗ_ball, 𝒥.
  // REQUIRES: `obs` holds kTossCatchObs floats.
  void WriteArmObservation(Hand hand, int ball, float* obs) const;

  Vec2 palm_position(Hand hand) const;
  Vec2 palm_velocity(Hand hand) const;
  Vec2 ball_position(int ball) const;
  Vec2 ball_velocity(int ball) const;
  BallMode mode(int ball) const { return balls_[ball].mode; }
  Hand holder(int ball) const { return balls_[ball].holder; }
  // The ball `hand` holds, or −1.
  int held_by(Hand hand) const;
  bool diverged() const { return diverged_; }
  double time() const { return data_->time; }
  const TossSpec& spec() const { return *spec_; }
  mjData* data() { return data_.get(); }
  const mjData* data() const { return data_.get(); }

 private:
  void PlaceBall(int ball, Vec2 position, Vec2 velocity);
  void FollowPalms();

  std::shared_ptr<const TossSpec> spec_;
  const mjModel* model_;
  MjDataPtr data_;
  std::array<BallState, kTossBalls> balls_{};
  std::optional<double> wind_override_;
  std::array<std::array<double, kTossJoints>, 2> target_{};      // world joint angles
  std::array<std::array<double, kTossJoints>, 2> prev_speed_{};  // ω before the last Step
  // Positions before the last Step (a ball placed since then: its placed position).
  std::array<Vec2, kTossBalls> prev_ball_{};
  std::array<Vec2, 2> prev_palm_{};
  bool diverged_ = false;
};

// The predicted landing of a released ball: where and when (since the release) it comes back
// down through height `z` under gravity `g` alone. time < 0 if it never does.
struct BallisticLanding {
  double x = 0, time = -1;
};
BallisticLanding PredictLanding(Vec2 position, Vec2 velocity, double z, double g);

// A good throw (the throw task's completion): released at `position` with `velocity` by
// `thrower` as a throw of `value`, it comes down at hand_z within catch_radius of the catching
// hand's home point and within 0.1 s of the schedule's flight time (Eq. 1).
bool IsGoodThrow(const TossSpec& spec, Hand thrower, int value, Vec2 position, Vec2 velocity);

}  // namespace juggle::toss

#endif  // JUGGLE_ENVS_TOSS_WORLD_H_

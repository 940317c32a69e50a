// TossSpec: the fixed part of a toss-juggling run (docs/toss.md) — the compiled planar two-arm
// model, the joint and ball addresses, the home pose and the siteswap timing — and the factory
// of TossTaskEnv (the single-arm training tasks) or TossLoopEnv (in-loop training, toss.loop).
// The two-arm runtime (envs/toss/juggler.h) uses the same spec. Conventions: the frontal x–z plane, x to the juggler's left; the right arm is
// the policy's frame and the left arm is its mirror image (x → −x, every hinge angle → −angle).
#ifndef JUGGLE_ENVS_TOSS_SPEC_H_
#define JUGGLE_ENVS_TOSS_SPEC_H_

#include <array>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <mujoco/mujoco.h>

#include "absl/status/statusor.h"
#include "common/config_loader.h"
#include "common/eigen_policy.h"
#include "envs/toss/siteswap.h"
#include "envs/toss/dims.h"
#include "envs/env.h"
#include "envs/mujoco_model.h"

namespace juggle::toss {

constexpr int kTossBalls = kTossModelBalls;

// Joint addresses of one arm, in 𝒥 order {neck, shoulder, elbow, wrist}. The neck is shared
// by both arms.
struct TossArmJoints {
  std::array<int, kTossJoints> qpos{};
  std::array<int, kTossJoints> dof{};
  int palm_site = -1;
};

struct TossBallJoints {
  int qpos_x = -1, qpos_z = -1, dof_x = -1, dof_z = -1;
  double origin_x = 0, origin_z = 0;  // world position at qpos 0
};

class TossSpec : public EnvSpec {
 public:
  // Compiles the config's toss model, or loads config.model_mjb when the config came stored
  // with its model (errors name the config field or the MJCF error), and
  // resolves joints, palms and balls; sets the arm joints' damping to kd (implicit in Euler).
  // INVALID_ARGUMENT if the model's timestep is not 10 ms or the home point is out of reach.
  static absl::StatusOr<std::shared_ptr<const TossSpec>> Create(const LoadedConfig& config);
  static absl::StatusOr<std::shared_ptr<const TossSpec>> CreateFromCompiled(
      const LoadedConfig& config, const std::string& model_mjb);
  TossSpec(const TossSpec&) = delete;
  TossSpec& operator=(const TossSpec&) = delete;

  int obs_dim() const override;
  int act_dim() const override { return kTossJoints; }
  const ControlGraph& graph() const override { return *config_.graph; }
  std::string family() const override { return "toss"; }
  const mjModel* model() const override { return model_.get(); }
  double control_dt() const override { return dt(); }
  std::vector<std::string> outcome_names() const override;
  std::unique_ptr<Env> NewEnv(Rng rng) const override;

  const config::TossConfig& toss() const { return config_.run.toss(); }
  const LoadedConfig& config() const { return config_; }
  // Locates fields of the toss section in the config file.
  const SourceLocator& locator() const { return config_.family_locator; }
  const TossArmJoints& arm(Hand hand) const { return arms_[static_cast<int>(hand)]; }
  const TossBallJoints& ball(int b) const { return balls_[b]; }
  // Home joint angles of the right arm (𝒥 order); the left arm's are their negatives.
  const std::array<double, kTossJoints>& home() const { return home_; }
  // +1 for the right arm, −1 for the left: multiplies x coordinates and joint angles.
  static double MirrorSign(Hand hand) { return hand == Hand::kRight ? 1.0 : -1.0; }
  // World home point of `hand`'s palm (x, z).
  double home_x(Hand hand) const { return MirrorSign(hand) * toss().hand_x(); }
  double home_z() const { return toss().hand_z(); }
  // Siteswap timing with the config's P_hand, D_ratio and hand separation 2·|hand_x|.
  const ThrowPhysicsParams& timing() const { return timing_; }
  double dt() const { return model_->opt.timestep; }

  // In-loop training (toss.loop set): the patterns and the frozen partner policies.
  bool in_loop() const { return toss().has_loop(); }
  const std::vector<Siteswap>& loop_patterns() const { return loop_patterns_; }
  const EigenPolicy* loop_catcher() const { return loop_catcher_ ? &*loop_catcher_ : nullptr; }
  const EigenPolicy* loop_thrower() const { return loop_thrower_ ? &*loop_thrower_ : nullptr; }

 private:
  TossSpec(LoadedConfig config, MjModelPtr model);
  static absl::StatusOr<std::shared_ptr<const TossSpec>> Build(const LoadedConfig& config,
                                                              MjModelPtr model);
  absl::Status Resolve();
  absl::Status ResolveLoop();

  LoadedConfig config_;
  MjModelPtr model_;
  std::array<TossArmJoints, 2> arms_;
  std::array<TossBallJoints, kTossBalls> balls_;
  std::array<double, kTossJoints> home_{};
  ThrowPhysicsParams timing_;
  std::vector<Siteswap> loop_patterns_;
  std::optional<EigenPolicy> loop_catcher_, loop_thrower_;
};

}  // namespace juggle::toss

#endif  // JUGGLE_ENVS_TOSS_SPEC_H_

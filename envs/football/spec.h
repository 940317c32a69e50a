// FootballSpec: what never changes during a football run (proto/envs/football.proto): the
// compiled pitch with the humanoid and the ball, the joints and gains, the standing pose, where
// the kicking foot stands. Built once, then shared read-only by every env on every thread.
#ifndef JUGGLE_ENVS_FOOTBALL_SPEC_H_
#define JUGGLE_ENVS_FOOTBALL_SPEC_H_

#include <memory>
#include <string>
#include <vector>

#include <mujoco/mujoco.h>

#include "absl/status/statusor.h"
#include "common/config_loader.h"
#include "envs/env.h"
#include "envs/football/pitch.h"
#include "envs/football/trap_episode.h"
#include "envs/geom_extent.h"
#include "envs/humanoid/humanoid.h"
#include "envs/mujoco_model.h"

namespace juggle::football {

using humanoid::CharacterPose;
constexpr int kNumActions = humanoid::kNumActuatedDofs;
// Observation: root height, orientation (4), chest and neck rotations (8), the other joints'
// positions (28), root linear and angular velocity (6), joint velocities (28), the ball's
// position relative to the root, velocity and spin (9), the kick's target velocity (3), the
// time to the scripted kick's start (1), whether the ball was touched (1).
constexpr int kObservationSize = 1 + 4 + 8 + 28 + 6 + 28 + 9 + 3 + 1 + 1;

class FootballSpec : public EnvSpec {
 public:
  // Compiles the config's model (or loads config.model_mjb) and resolves everything against
  // it. Errors name the config file, line and field, or the MJCF problem.
  static absl::StatusOr<std::shared_ptr<const FootballSpec>> Create(const LoadedConfig& config);
  static absl::StatusOr<std::shared_ptr<const FootballSpec>> CreateFromCompiled(
      const LoadedConfig& config, const std::string& model_mjb);
  FootballSpec(const FootballSpec&) = delete;
  FootballSpec& operator=(const FootballSpec&) = delete;

  std::string family() const override { return "football"; }
  int obs_dim() const override { return kObservationSize; }
  int act_dim() const override { return kNumActions; }
  double control_dt() const override { return football().sim_dt() * football().substeps(); }
  const ControlGraph& graph() const override { return *config_.graph; }  // empty
  const mjModel* model() const override { return model_.get(); }
  std::vector<std::string> outcome_names() const override;
  std::unique_ptr<Env> NewEnv(Rng rng) const override;
  // One trap, kick or trap-then-kick per episode: no juggles to count.
  bool counts_juggles() const override { return false; }
  // PhysicsFC's metrics over the episodes' trap and kick metrics (metrics.h): "tsr=... ksr=...".
  std::string EvaluationLine(
      const std::vector<std::vector<NamedValue>>& episode_metrics) const override;

  const LoadedConfig& config() const { return config_; }
  const config::FootballConfig& football() const { return config_.run.football(); }
  const humanoid::Joints& joints() const { return joints_; }
  const PitchBall& ball() const { return ball_; }
  // The standing pose: root at (0, 0, root_height), upright, facing +x, joints at rest.
  const CharacterPose& standing_pose() const { return standing_; }
  int root_body() const { return root_body_; }
  // The kicking (right) foot: its body, its geom (box or boot) and the geom's bounds
  // (envs/geom_extent.h), and the bounds' centre when standing (the same point for a box and a
  // boot of its length).
  int kick_foot_body() const { return kick_foot_body_; }
  int kick_foot_geom() const { return kick_foot_geom_; }
  const GeomBounds& kick_foot_bounds() const { return kick_foot_bounds_; }
  const double* kick_foot_standing() const { return kick_foot_standing_; }
  // The TRAP and TRAP_KICK tasks' parts and arms (trap_episode.h; empty for KICK).
  const TrapBodies& trap_bodies() const { return trap_bodies_; }
  // An episode starts with a pass to trap (TRAP, TRAP_KICK); trap_kick(): a kick follows it.
  bool trap() const { return football().task() != config::KICK; }
  bool trap_kick() const { return football().task() == config::TRAP_KICK; }

 private:
  FootballSpec(LoadedConfig config, MjModelPtr model);
  static absl::StatusOr<std::shared_ptr<const FootballSpec>> Build(const LoadedConfig& config,
                                                                  MjModelPtr model);

  LoadedConfig config_;
  MjModelPtr model_;
  humanoid::Joints joints_;
  PitchBall ball_;
  CharacterPose standing_{};
  int root_body_ = -1, kick_foot_body_ = -1, kick_foot_geom_ = -1;
  GeomBounds kick_foot_bounds_;
  double kick_foot_standing_[3] = {0, 0, 0};
  TrapBodies trap_bodies_;
};

}  // namespace juggle::football

#endif  // JUGGLE_ENVS_FOOTBALL_SPEC_H_

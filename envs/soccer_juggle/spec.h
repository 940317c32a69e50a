// JuggleSpec: everything an environment needs that never changes during a run — the compiled
// MuJoCo model, the validated control graph, the per-joint PD gains, the resolved per-node
// data (allowed contact bodies, keyframes, around-the-world angle tables). Built once,
// validated once, then shared read-only by every env on every thread (thread-safe to read).
#ifndef JUGGLE_ENVS_SOCCER_JUGGLE_SPEC_H_
#define JUGGLE_ENVS_SOCCER_JUGGLE_SPEC_H_

#include <array>
#include <memory>
#include <string>
#include <vector>

#include <mujoco/mujoco.h>

#include "absl/status/statusor.h"
#include "common/config_loader.h"
#include "common/control_graph.h"
#include "envs/soccer_juggle/graph_cursor.h"
#include "envs/env.h"
#include "envs/humanoid/humanoid.h"
#include "envs/planning_model.h"
#include "envs/mujoco_model.h"

namespace juggle::soccer_juggle {

// The humanoid's joints, gains and pose type (envs/humanoid/humanoid.h), under their names here.
using humanoid::ActuatedJoint;
using humanoid::CharacterPose;
using humanoid::JointId;
using humanoid::kCharacterNq;
using humanoid::kCharacterNv;
using humanoid::kJointNames;
using humanoid::kNumJoints;
using humanoid::kChest;
using humanoid::kNeck;
using humanoid::kRightShoulder;
using humanoid::kRightElbow;
using humanoid::kLeftShoulder;
using humanoid::kLeftElbow;
using humanoid::kRightHip;
using humanoid::kRightKnee;
using humanoid::kRightAnkle;
using humanoid::kLeftHip;
using humanoid::kLeftKnee;
using humanoid::kLeftAnkle;

constexpr int kNumActions = humanoid::kNumActuatedDofs;  // actuated DoF of the humanoid
// The zero action: the base controller alone drives the character.
inline constexpr float kZeroAction[kNumActions] = {};
constexpr int kObsBase = 88;       // observation floats before the three node one-hots

// Observation size for a control graph with `num_nodes` nodes.
constexpr int ObservationSize(int num_nodes) { return kObsBase + 3 * num_nodes; }
constexpr int kBallErrorObs = 6;  // appended by env.ball_error_observation

// Per-node data resolved against the model.
// One joint axis a node's kick variable moves (config::KickVariableSpec, resolved).
struct KickVariableMove {
  JointId joint = kChest;
  int axis = 0;  // 0 = x, 1 = y, 2 = z; 0 for a hinge
  double gain = 1;
  // config::KickVariableSpec::SPEED: the move's envelope is the speed one (plan.cc).
  bool speed = false;
};

// The most kick variables a node declares (NodeSpec.kick_variable): the planner's four angles.
constexpr int kMaxNodeKickVariables = 4;

struct NodeRuntime {
  std::vector<char> contact_allowed;   // by body id
  // Keyframes as full character poses (only for keyframe generators), sorted by phase.
  std::vector<double> keyframe_phase;
  std::vector<CharacterPose> keyframe_pose;
  // Around-the-world: foot body and desired ψ (rad) at equally spaced phases over the node.
  int atw_foot_body = -1;
  std::vector<double> atw_angle;
  double atw_max_chord2 = 0;   // squared chord length of the allowed angle
  int atw_skip_steps = 0;
  // Stall: body the ball must stay near.
  int stall_body = -1;
  double stall_max_distance = 0;
  // The node's declared kick variables (empty: the generator's own), each its joint axes.
  std::vector<std::vector<KickVariableMove>> kick_variables;
};

class JuggleSpec : public EnvSpec {
 public:
  // Compiles the model named by the config (or loads config.model_mjb when the config came
  // stored with its model) and resolves everything against it. Errors (INVALID_ARGUMENT /
  // NOT_FOUND) name the config file, line and field, or the MJCF error.
  static absl::StatusOr<std::shared_ptr<const JuggleSpec>> Create(const LoadedConfig& config);
  // As Create, from a model compiled elsewhere (mj_saveModel bytes, as the learner ships it).
  static absl::StatusOr<std::shared_ptr<const JuggleSpec>> CreateFromCompiled(
      const LoadedConfig& config, const std::string& model_mjb);
  // The planning variant of `exact` (envs/planning_model.h): its config and model with the
  // options applied (sim_dt and the model's timestep × timestep_factor, substeps ÷ it), sharing
  // exact's fingerprint. INVALID_ARGUMENT when the factor does not divide the substeps.
  static absl::StatusOr<std::shared_ptr<const JuggleSpec>> CreatePlanningVariant(
      const JuggleSpec& exact, const PlanningModelOptions& options);
  JuggleSpec(const JuggleSpec&) = delete;
  JuggleSpec& operator=(const JuggleSpec&) = delete;

  std::string family() const override { return "soccer_juggle"; }
  const mjModel* model() const override { return model_.get(); }
  const LoadedConfig& config() const { return config_; }
  const config::EnvConfig& env() const { return config_.run.soccer_juggle().env(); }
  // Locates fields of `env` in the config file.
  SourceLocator env_locator() const { return config_.family_locator.Nested({{"env"}}); }
  const ControlGraph& graph() const override { return *config_.graph; }
  const GraphCursor& cursor() const { return cursor_; }
  const ActuatedJoint& joint(int j) const { return joints_[j]; }
  const humanoid::Joints& joints() const { return joints_; }
  const NodeRuntime& node_runtime(int n) const { return nodes_[n]; }
  const CharacterPose& rest_pose() const { return rest_pose_; }

  int obs_dim() const override {
    return ObservationSize(graph().num_nodes()) + (env().ball_error_observation() ? kBallErrorObs : 0) +
           (env().previous_action_observation() ? kNumActions : 0);
  }
  int act_dim() const override { return kNumActions; }
  std::unique_ptr<Env> NewEnv(Rng rng) const override;
  double control_dt() const override { return env().sim_dt() * env().substeps(); }
  std::vector<std::string> outcome_names() const override;
  // node (index into graph node names), phase.
  std::vector<AnnotationChannel> annotation_channels() const override;
  int root_body() const { return root_body_; }
  int ball_body() const { return ball_body_; }
  int ball_geom() const { return ball_geom_; }
  int ball_qpos() const { return ball_qpos_; }
  int ball_dof() const { return ball_dof_; }

 private:
  JuggleSpec(LoadedConfig config, MjModelPtr model);
  static absl::StatusOr<std::shared_ptr<const JuggleSpec>> Build(const LoadedConfig& config,
                                                                MjModelPtr model);

  LoadedConfig config_;
  MjModelPtr model_;
  GraphCursor cursor_;
  humanoid::Joints joints_;
  std::vector<NodeRuntime> nodes_;
  CharacterPose rest_pose_{};
  int root_body_ = -1, ball_body_ = -1, ball_geom_ = -1, ball_qpos_ = -1, ball_dof_ = -1;

  friend class JuggleSpecBuilder;
};

}  // namespace juggle::soccer_juggle

#endif  // JUGGLE_ENVS_SOCCER_JUGGLE_SPEC_H_

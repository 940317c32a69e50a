#include "envs/soccer_juggle/spec.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "absl/strings/str_cat.h"
#include "common/status_macros.h"
#include "envs/humanoid/pose.h"
#include "envs/mujoco_model.h"
#include "envs/soccer_juggle/outcomes.h"
#include "envs/soccer_juggle/reference_pose.h"

namespace juggle::soccer_juggle {

namespace {

absl::Status Invalid(const SourceLocator& where, const FieldPath& path, const std::string& what) {
  return absl::InvalidArgumentError(absl::StrCat(where.Where(path), ": ", what));
}

using humanoid::JointIdByName;

}  // namespace

// Builds a JuggleSpec step by step; a friend so the spec itself stays immutable.
class JuggleSpecBuilder {
 public:
  static absl::Status ResolveJoints(JuggleSpec* s);
  static absl::Status ResolveRestPose(JuggleSpec* s);
  static absl::Status ResolveNodes(JuggleSpec* s);
  static absl::Status ApplyRotation(const JuggleSpec& s, const config::JointRotation& r,
                                    const SourceLocator& where, const FieldPath& path,
                                    CharacterPose* pose);
  static absl::Status ResolveKeyframes(JuggleSpec* s, int n);
  static absl::Status ResolveKickVariables(JuggleSpec* s, int n);
  static void DeriveAroundTheWorldAngles(JuggleSpec* s, int n);
};

JuggleSpec::JuggleSpec(LoadedConfig config, MjModelPtr model)
    : config_(std::move(config)),
      model_(std::move(model)),
      cursor_(config_.graph.get(), env().sim_dt() * env().substeps(), env().gravity(),
              env().carry_phase()) {}

std::vector<std::string> JuggleSpec::outcome_names() const {
  std::vector<std::string> names = CommonOutcomeNames();
  for (const char* name : kOutcomeNames) names.push_back(name);
  return names;
}

std::vector<AnnotationChannel> JuggleSpec::annotation_channels() const {
  AnnotationChannel node{"node", {}};
  for (int n = 0; n < graph().num_nodes(); ++n) node.labels.push_back(graph().node(n).name);
  return {node, AnnotationChannel{"phase", {}}};
}

absl::StatusOr<std::shared_ptr<const JuggleSpec>> JuggleSpec::Create(const LoadedConfig& config) {
  if (!config.model_mjb.empty()) return CreateFromCompiled(config, config.model_mjb);
  const config::EnvConfig& env = config.run.soccer_juggle().env();
  ASSIGN_OR_RETURN(MjModelPtr model,
                   LoadModelXml(ResolvePath(config.config_dir, env.model_file()),
                                config.family_locator.Nested({{"env"}}).Where({{"model_file"}})));
  return Build(config, std::move(model));
}

absl::StatusOr<std::shared_ptr<const JuggleSpec>> JuggleSpec::CreateFromCompiled(
    const LoadedConfig& config, const std::string& model_mjb) {
  ASSIGN_OR_RETURN(MjModelPtr model, LoadModelCompiled(model_mjb));
  return Build(config, std::move(model));
}

absl::StatusOr<std::shared_ptr<const JuggleSpec>> JuggleSpec::CreatePlanningVariant(
    const JuggleSpec& exact, const PlanningModelOptions& options) {
  const int factor = options.timestep_factor;
  const int substeps = exact.env().substeps();
  if (factor < 1 || substeps % factor != 0) {
    return absl::InvalidArgumentError(absl::StrCat(
        "planner.planning_model.timestep_factor ", factor, " does not divide the env's ",
        substeps, " substeps per control step"));
  }
  LoadedConfig config = exact.config();
  config::EnvConfig* env = config.run.mutable_soccer_juggle()->mutable_env();
  env->set_sim_dt(env->sim_dt() * factor);
  env->set_substeps(substeps / factor);
  MjModelPtr model(mj_copyModel(nullptr, exact.model()));
  model->opt.timestep = env->sim_dt();
  if (options.solver_iterations > 0) model->opt.iterations = options.solver_iterations;
  if (options.solver_tolerance > 0) model->opt.tolerance = options.solver_tolerance;
  if (options.pyramidal_cone) model->opt.cone = mjCONE_PYRAMIDAL;
  ASSIGN_OR_RETURN(std::shared_ptr<const JuggleSpec> built, Build(config, std::move(model)));
  // Build made it; nothing else holds it yet.
  std::const_pointer_cast<JuggleSpec>(built)->ShareFingerprint(exact);
  return built;
}

absl::StatusOr<std::shared_ptr<const JuggleSpec>> JuggleSpec::Build(const LoadedConfig& config,
                                                                   MjModelPtr owned_model) {
  const config::EnvConfig& env = config.run.soccer_juggle().env();
  mjModel* model = owned_model.get();
  std::shared_ptr<JuggleSpec> spec(new JuggleSpec(config, std::move(owned_model)));
  const SourceLocator env_locator = spec->env_locator();
  if (std::abs(model->opt.timestep - env.sim_dt()) > 1e-12) {
    return Invalid(env_locator, {{"sim_dt"}},
                   absl::StrCat("sim_dt ", env.sim_dt(), " differs from the model's timestep ",
                                model->opt.timestep));
  }
  if (std::abs(-model->opt.gravity[2] - env.gravity()) > 1e-9) {
    return Invalid(env_locator, {{"gravity"}},
                   absl::StrCat("gravity ", env.gravity(), " differs from the model's ",
                                -model->opt.gravity[2]));
  }
  spec->root_body_ = mj_name2id(model, mjOBJ_BODY, "root");
  spec->ball_body_ = mj_name2id(model, mjOBJ_BODY, "ball");
  spec->ball_geom_ = mj_name2id(model, mjOBJ_GEOM, "ball");
  const int ball_joint = mj_name2id(model, mjOBJ_JOINT, "ball");
  if (spec->root_body_ < 0 || spec->ball_body_ < 0 || spec->ball_geom_ < 0 || ball_joint < 0 ||
      model->jnt_type[ball_joint] != mjJNT_FREE) {
    return Invalid(env_locator, {{"model_file"}},
                   "the model needs a body 'root' and a free body 'ball' with a geom 'ball'");
  }
  spec->ball_qpos_ = model->jnt_qposadr[ball_joint];
  spec->ball_dof_ = model->jnt_dofadr[ball_joint];
  RETURN_IF_ERROR(JuggleSpecBuilder::ResolveJoints(spec.get()));
  RETURN_IF_ERROR(JuggleSpecBuilder::ResolveRestPose(spec.get()));
  RETURN_IF_ERROR(JuggleSpecBuilder::ResolveNodes(spec.get()));
  spec->SetFingerprint(config.run.soccer_juggle().SerializeAsString());
  return std::shared_ptr<const JuggleSpec>(std::move(spec));
}

absl::Status JuggleSpecBuilder::ResolveJoints(JuggleSpec* s) {
  mjModel* m = s->model_.get();
  const SourceLocator where = s->env_locator();
  absl::StatusOr<humanoid::Joints> joints = humanoid::ResolveJoints(m);
  if (!joints.ok()) return Invalid(where, {{"model_file"}}, std::string(joints.status().message()));
  s->joints_ = *joints;
  const config::EnvConfig& env = s->env();
  for (int i = 0; i < env.joint_gains_size(); ++i) {
    const config::JointGains& override_gains = env.joint_gains(i);
    const int j = JointIdByName(override_gains.joint());
    if (j < 0) {
      return Invalid(where, {{"joint_gains", i}, {"joint"}},
                     absl::StrCat("unknown joint '", override_gains.joint(), "'"));
    }
    if (override_gains.has_kp()) s->joints_[j].kp = override_gains.kp();
    if (override_gains.has_kd()) s->joints_[j].kd = override_gains.kd();
    if (override_gains.has_torque_scale()) {
      s->joints_[j].torque_scale = override_gains.torque_scale();
    }
  }
  // Written before any env exists; the model is read-only afterwards.
  humanoid::WriteJointDamping(s->joints_, m);
  return absl::OkStatus();
}

absl::Status JuggleSpecBuilder::ApplyRotation(const JuggleSpec& s, const config::JointRotation& r,
                                              const SourceLocator& where, const FieldPath& path,
                                              CharacterPose* pose) {
  std::string field;
  absl::Status status = humanoid::ApplyJointRotation(s.joints(), r, pose, &field);
  if (status.ok()) return status;
  FieldPath p = path;
  p.push_back({field});
  return Invalid(where, p, std::string(status.message()));
}

absl::Status JuggleSpecBuilder::ResolveRestPose(JuggleSpec* s) {
  CharacterPose& pose = s->rest_pose_;
  std::fill(pose.begin(), pose.end(), 0.0);
  for (int j = 0; j < kNumJoints; ++j) {
    if (s->joints_[j].dofs == 3) pose[s->joints_[j].qpos_adr] = 1.0;  // identity quaternion
  }
  const config::EnvConfig& env = s->env();
  if (env.rest_pose_size() == 0) {
    // The release's arm pose: elbows bent 1.57, shoulders abducted 0.7 about x.
    SetHinge(*s, kRightElbow, 1.57, &pose);
    SetHinge(*s, kLeftElbow, 1.57, &pose);
    SetBallJointAxisRotation(*s, kRightShoulder, 0, -0.7, &pose);
    SetBallJointAxisRotation(*s, kLeftShoulder, 0, 0.7, &pose);
  }
  for (int i = 0; i < env.rest_pose_size(); ++i) {
    RETURN_IF_ERROR(ApplyRotation(*s, env.rest_pose(i), s->env_locator(),
                                  {{"rest_pose", i}}, &pose));
  }
  return absl::OkStatus();
}

absl::Status JuggleSpecBuilder::ResolveKeyframes(JuggleSpec* s, int n) {
  const config::Keyframes& kf = s->graph().node(n).spec.pose().keyframes();
  const SourceLocator& where = s->config_.graph_locator;
  const FieldPath base = {{"node", n}, {"pose"}, {"keyframes"}};
  NodeRuntime& rt = s->nodes_[n];
  if (kf.frame_size() == 0) {
    FieldPath p = base;
    return Invalid(where, p, "keyframes need at least one frame");
  }
  double last_phase = -1;
  for (int f = 0; f < kf.frame_size(); ++f) {
    const config::Keyframe& frame = kf.frame(f);
    FieldPath fp = base;
    fp.push_back({"frame", f});
    if (frame.phase() < last_phase || frame.phase() < 0 || frame.phase() > 1) {
      FieldPath p = fp;
      p.push_back({"phase"});
      return Invalid(where, p, "frame phases must be in [0, 1] and non-decreasing");
    }
    last_phase = frame.phase();
    CharacterPose pose = s->rest_pose_;
    pose[0] = frame.root_x();
    pose[1] = frame.root_y();
    pose[2] = frame.root_height();
    double lean[4] = {1, 0, 0, 0};
    if (frame.root_rotation_size() == 3) {
      double v[3] = {frame.root_rotation(0), frame.root_rotation(1), frame.root_rotation(2)};
      const double angle = mju_normalize3(v);
      if (angle > 1e-12) mju_axisAngle2Quat(lean, v, angle);
    } else if (frame.root_rotation_size() != 0) {
      FieldPath p = fp;
      p.push_back({"root_rotation"});
      return Invalid(where, p, "root_rotation takes 3 values");
    }
    mju_mulQuat(pose.data() + 3, kUprightQuat, lean);
    for (int r = 0; r < frame.joint_size(); ++r) {
      FieldPath p = fp;
      p.push_back({"joint", r});
      RETURN_IF_ERROR(ApplyRotation(*s, frame.joint(r), where, p, &pose));
    }
    rt.keyframe_phase.push_back(frame.phase());
    rt.keyframe_pose.push_back(pose);
  }
  return absl::OkStatus();
}

// ψ_d(φ) = atan2(foot_z − ball_z, foot_y − ball_y) of the reference pose and ball reference,
// by forward kinematics, at 16 equally spaced phases of the node's half cycle.
void JuggleSpecBuilder::DeriveAroundTheWorldAngles(JuggleSpec* s, int n) {
  constexpr int kBins = 16;
  const GraphNode& node = s->graph().node(n);
  NodeRuntime& rt = s->nodes_[n];
  MjDataPtr d(mj_makeData(s->model_.get()));
  CursorState cursor;
  cursor.current = n;
  cursor.next = n;
  cursor.apex_height = NominalApexHeight(node.spec, s->env().gravity());
  cursor.phase_speed = s->control_dt() / (2.0 * s->cursor_.HalfCycleSeconds(n, cursor.apex_height));
  const double start = node.stage == config::UP ? 0.5 : 0.0;
  for (int b = 0; b < kBins; ++b) {
    const double phase = start + 0.5 * (b + 0.5) / kBins;
    CharacterPose pose;
    ComputeReferencePose(*s, n, phase, &pose);
    mju_copy(d->qpos, pose.data(), kCharacterNq);
    mj_kinematics(s->model_.get(), d.get());
    const BallReference ball = s->cursor_.DesiredBall(cursor, phase);
    const double* foot = d->xpos + 3 * rt.atw_foot_body;
    const double ball_y = pose[1] + ball.y;
    rt.atw_angle.push_back(std::atan2(foot[2] - ball.z, foot[1] - ball_y));
  }
}

absl::Status JuggleSpecBuilder::ResolveKickVariables(JuggleSpec* s, int n) {
  const config::NodeSpec& spec = s->graph().node(n).spec;
  const SourceLocator& where = s->config_.graph_locator;
  const std::string& name = s->graph().node(n).name;
  if (spec.kick_variable_size() > kMaxNodeKickVariables) {
    return Invalid(where, {{"node", n}, {"kick_variable", kMaxNodeKickVariables}},
                   absl::StrCat("node '", name, "' declares ", spec.kick_variable_size(),
                                " kick variables; the planner searches at most ",
                                kMaxNodeKickVariables));
  }
  std::vector<std::vector<KickVariableMove>>& out = s->nodes_[n].kick_variables;
  for (int v = 0; v < spec.kick_variable_size(); ++v) {
    const config::KickVariableSpec& variable = spec.kick_variable(v);
    if (variable.move_size() == 0) {
      return Invalid(where, {{"node", n}, {"kick_variable", v}},
                     absl::StrCat("node '", name, "': kick variable ", v, " moves no joint"));
    }
    std::vector<KickVariableMove>& moves = out.emplace_back();
    for (int m = 0; m < variable.move_size(); ++m) {
      const config::JointAxis& axis = variable.move(m);
      const FieldPath path = {{"node", n}, {"kick_variable", v}, {"move", m}};
      const int j = JointIdByName(axis.joint());
      if (j < 0) {
        FieldPath p = path;
        p.push_back({"joint"});
        return Invalid(where, p,
                       absl::StrCat("node '", name, "': '", axis.joint(),
                                    "' is not a joint the character actuates"));
      }
      KickVariableMove move;
      move.joint = static_cast<JointId>(j);
      move.gain = axis.gain();
      move.speed = variable.envelope() == config::KickVariableSpec::SPEED;
      const bool ball = s->joint(move.joint).dofs == 3;
      const std::string& a = axis.axis();
      if (ball != (a.size() == 1 && a[0] >= 'x' && a[0] <= 'z') || (!ball && !a.empty())) {
        FieldPath p = path;
        p.push_back({"axis"});
        return Invalid(where, p,
                       absl::StrCat("node '", name, "': '", axis.joint(), "' ",
                                    ball ? "is a ball joint: name its axis, x, y or z"
                                         : "is a hinge: it takes no axis"));
      }
      if (ball) move.axis = a[0] - 'x';
      moves.push_back(move);
    }
  }
  return absl::OkStatus();
}

absl::Status JuggleSpecBuilder::ResolveNodes(JuggleSpec* s) {
  const mjModel* m = s->model_.get();
  const ControlGraph& graph = s->graph();
  const SourceLocator& where = s->config_.graph_locator;
  auto body_id = [&](const std::string& name, const FieldPath& path) -> absl::StatusOr<int> {
    const int id = mj_name2id(m, mjOBJ_BODY, name.c_str());
    if (id <= 0 || id == s->ball_body_) {
      return Invalid(where, path, absl::StrCat("'", name, "' is not a body of the character"));
    }
    return id;
  };
  s->nodes_.resize(graph.num_nodes());
  for (int n = 0; n < graph.num_nodes(); ++n) {
    const config::NodeSpec& spec = graph.node(n).spec;
    NodeRuntime& rt = s->nodes_[n];
    rt.contact_allowed.assign(m->nbody, 0);
    for (int b = 0; b < spec.contact_body_size(); ++b) {
      ASSIGN_OR_RETURN(const int id,
                       body_id(spec.contact_body(b), {{"node", n}, {"contact_body", b}}));
      rt.contact_allowed[id] = 1;
    }
    if (spec.pose().has_keyframes()) RETURN_IF_ERROR(ResolveKeyframes(s, n));
    RETURN_IF_ERROR(ResolveKickVariables(s, n));
    config::Side swing_side;
    if (spec.has_kick_feedback() &&
        (spec.stage() != config::DOWN || !SwingingLeg(spec.pose(), &swing_side))) {
      return Invalid(where, {{"node", n}, {"kick_feedback"}},
                     absl::StrCat("node '", graph.node(n).name,
                                  "': kick_feedback acts only in a DOWN node with a leg swing "
                                  "or keyframes with a swing_side (the base controller's swing "
                                  "before the contact)"));
    }
    if (spec.has_head_feedback() && !spec.pose().has_head_dip() &&
        !spec.pose().has_chest_lean()) {
      return Invalid(where, {{"node", n}, {"head_feedback"}},
                     absl::StrCat("node '", graph.node(n).name,
                                  "': head_feedback acts only in a node with a head_dip pose "
                                  "(a header) or a chest_lean pose"));
    }
    if (spec.pose_lead_in() > 0 && spec.stage() == config::UP) {
      return Invalid(where, {{"node", n}, {"pose_lead_in"}},
                     absl::StrCat("node '", graph.node(n).name,
                                  "': pose_lead_in blends the UP node before it into this one; "
                                  "set it on a DOWN or STALL node"));
    }
    if (spec.has_stall()) {
      ASSIGN_OR_RETURN(rt.stall_body,
                       body_id(spec.stall().body(), {{"node", n}, {"stall"}, {"body"}}));
      rt.stall_max_distance = spec.stall().max_distance();
    }
    if (spec.has_around_the_world()) {
      const config::AroundTheWorldConstraint& atw = spec.around_the_world();
      ASSIGN_OR_RETURN(rt.atw_foot_body,
                       body_id(atw.foot_body(), {{"node", n}, {"around_the_world"}, {"foot_body"}}));
      const double max_angle = atw.max_angle_deg() * M_PI / 180.0;
      rt.atw_max_chord2 = 2.0 - 2.0 * std::cos(max_angle);
      rt.atw_skip_steps = atw.skip_steps();
      if (atw.angle_deg_size() > 0) {
        for (double a : atw.angle_deg()) rt.atw_angle.push_back(a * M_PI / 180.0);
      } else {
        DeriveAroundTheWorldAngles(s, n);
      }
    }
  }
  return absl::OkStatus();
}

}  // namespace juggle::soccer_juggle

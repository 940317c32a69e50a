#include "envs/football/spec.h"

#include <algorithm>
#include <cmath>

#include "absl/strings/str_cat.h"
#include "common/status_macros.h"
#include "envs/football/metrics.h"
#include "envs/football/outcomes.h"
#include "envs/humanoid/pose.h"

namespace juggle::football {
namespace {

absl::Status Invalid(const SourceLocator& where, const FieldPath& path, const std::string& what) {
  return absl::InvalidArgumentError(absl::StrCat(where.Where(path), ": ", what));
}

}  // namespace

FootballSpec::FootballSpec(LoadedConfig config, MjModelPtr model)
    : config_(std::move(config)), model_(std::move(model)) {}

std::vector<std::string> FootballSpec::outcome_names() const {
  std::vector<std::string> names = CommonOutcomeNames();
  for (const char* name : kOutcomeNames) names.push_back(name);
  return names;
}

absl::StatusOr<std::shared_ptr<const FootballSpec>> FootballSpec::Create(
    const LoadedConfig& config) {
  if (!config.model_mjb.empty()) return CreateFromCompiled(config, config.model_mjb);
  ASSIGN_OR_RETURN(MjModelPtr model,
                   LoadModelXml(ResolvePath(config.config_dir, config.run.football().model_file()),
                                config.family_locator.Where({{"model_file"}})));
  return Build(config, std::move(model));
}

absl::StatusOr<std::shared_ptr<const FootballSpec>> FootballSpec::CreateFromCompiled(
    const LoadedConfig& config, const std::string& model_mjb) {
  ASSIGN_OR_RETURN(MjModelPtr model, LoadModelCompiled(model_mjb));
  return Build(config, std::move(model));
}

absl::StatusOr<std::shared_ptr<const FootballSpec>> FootballSpec::Build(const LoadedConfig& config,
                                                                      MjModelPtr owned_model) {
  const config::FootballConfig& f = config.run.football();
  const SourceLocator& where = config.family_locator;
  mjModel* model = owned_model.get();
  std::shared_ptr<FootballSpec> spec(new FootballSpec(config, std::move(owned_model)));
  if (std::abs(model->opt.timestep - f.sim_dt()) > 1e-12) {
    return Invalid(where, {{"sim_dt"}},
                   absl::StrCat("sim_dt ", f.sim_dt(), " differs from the model's timestep ",
                                model->opt.timestep));
  }
  absl::StatusOr<PitchBall> ball = FindPitchBall(model);
  if (!ball.ok()) return Invalid(where, {{"model_file"}}, std::string(ball.status().message()));
  spec->ball_ = *ball;
  absl::StatusOr<humanoid::Joints> joints = humanoid::ResolveJoints(model);
  if (!joints.ok()) return Invalid(where, {{"model_file"}}, std::string(joints.status().message()));
  spec->joints_ = *joints;
  spec->root_body_ = mj_name2id(model, mjOBJ_BODY, "root");
  spec->kick_foot_body_ = mj_name2id(model, mjOBJ_BODY, "right_ankle");
  spec->kick_foot_geom_ = mj_name2id(model, mjOBJ_GEOM, "right_foot");
  if (spec->root_body_ < 0 || spec->kick_foot_body_ < 0 || spec->kick_foot_geom_ < 0 ||
      model->geom_bodyid[spec->kick_foot_geom_] != spec->kick_foot_body_) {
    return Invalid(where, {{"model_file"}},
                   "the model needs a body 'root' and a body 'right_ankle' with a geom "
                   "'right_foot' (the kicking foot)");
  }
  // Written before any env exists; the model is read-only afterwards.
  humanoid::WriteJointDamping(spec->joints_, model);

  CharacterPose& pose = spec->standing_;
  pose = humanoid::ReleaseRestPose(spec->joints_);
  if (f.rest_pose_size() > 0) {
    // As soccer_juggle's env.rest_pose: the listed rotations on identity joints.
    std::fill(pose.begin(), pose.end(), 0.0);
    for (const humanoid::ActuatedJoint& joint : spec->joints_) {
      if (joint.dofs == 3) pose[joint.qpos_adr] = 1.0;
    }
    for (int i = 0; i < f.rest_pose_size(); ++i) {
      std::string field;
      if (absl::Status s = humanoid::ApplyJointRotation(spec->joints_, f.rest_pose(i), &pose, &field);
          !s.ok()) {
        return Invalid(where, {{"rest_pose", i}, {field}}, std::string(s.message()));
      }
    }
  }
  pose[0] = pose[1] = 0;
  pose[2] = f.root_height();
  std::copy(humanoid::kUprightRoot, humanoid::kUprightRoot + 4, pose.begin() + 3);
  // Where the kicking foot stands (forward kinematics of the standing pose).
  MjDataPtr d(mj_makeData(model));
  mju_copy(d->qpos, pose.data(), humanoid::kCharacterNq);
  mj_kinematics(model, d.get());
  spec->kick_foot_bounds_ = MeasureGeomBounds(model, spec->kick_foot_geom_);
  GeomBoundsCentre(spec->kick_foot_bounds_, model, d.get(), spec->kick_foot_standing_);
  if (f.task() == config::TRAP || f.task() == config::TRAP_KICK) {
    absl::StatusOr<TrapBodies> trap = ResolveTrapBodies(model, pose.data(), f.trap(), where);
    if (!trap.ok()) return trap.status();
    spec->trap_bodies_ = *std::move(trap);
    double highest = 0;
    for (config::TrapPart p : LobParts(f.trap())) {
      highest = std::max(highest, LobMeetingHeight(spec->trap_bodies_, p));
    }
    RETURN_IF_ERROR(ValidateTrapPasses(f.trap(), where, highest, spec->ball_.radius,
                                       -model->opt.gravity[2]));
  }
  spec->SetFingerprint(f.SerializeAsString());
  return std::shared_ptr<const FootballSpec>(std::move(spec));
}

std::string FootballSpec::EvaluationLine(
    const std::vector<std::vector<NamedValue>>& episode_metrics) const {
  FootballMetrics metrics;
  for (const std::vector<NamedValue>& episode : episode_metrics) {
    KickScore kick;
    TrapScore trap;
    bool attempted = false, trapped = false;
    for (const NamedValue& v : episode) {
      if (v.name == "trap_success") {
        trapped = true;
        trap.success = v.value > 0.5;
      } else if (v.name == "trap_handball") {
        trap.handball = v.value > 0.5;
      } else if (v.name == "trap_rbspt_mps") {
        trap.relative_speed = v.value;
        trap.measured_speed = true;
      } else if (v.name == "trap_kick_success") {
        metrics.AddTrapThenKick(v.value > 0.5);
      } else if (v.name == "kick_success") {
        attempted = true;
        kick.success = v.value > 0.5;
      } else if (v.name == "kick_direction_deviation_deg") {
        kick.direction_deviation_deg = v.value;
      } else if (v.name == "kick_speed_deviation_mps") {
        kick.speed_deviation_mps = v.value;
      }
    }
    if (attempted) metrics.Add(kick);
    if (trapped) metrics.Add(trap);
  }
  return metrics.SummaryLine();
}

}  // namespace juggle::football

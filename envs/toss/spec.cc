#include "envs/toss/spec.h"

#include <cmath>

#include "absl/strings/str_cat.h"
#include "common/status_macros.h"
#include "envs/mujoco_model.h"
#include "envs/toss/task_env.h"
#include "envs/toss/loop_env.h"
#include "envs/toss/outcomes.h"

namespace juggle::toss {
namespace {

const char* const kArmJointNames[2][kTossJoints] = {
    {"neck", "right_shoulder", "right_elbow", "right_wrist"},
    {"neck", "left_shoulder", "left_elbow", "left_wrist"}};
const char* const kPalmNames[2] = {"right_palm", "left_palm"};

// x of the direction of a link at hinge angle φ about +y, starting from straight down:
// the direction is (−sin φ, −cos φ).
double LinkX(double phi) { return -std::sin(phi); }

}  // namespace

TossSpec::TossSpec(LoadedConfig config, MjModelPtr model)
    : config_(std::move(config)), model_(std::move(model)) {}

absl::StatusOr<std::shared_ptr<const TossSpec>> TossSpec::Create(const LoadedConfig& config) {
  if (!config.model_mjb.empty()) return CreateFromCompiled(config, config.model_mjb);
  ASSIGN_OR_RETURN(MjModelPtr model,
                   LoadModelXml(ResolvePath(config.config_dir, config.run.toss().model_file()),
                                config.family_locator.Where({{"model_file"}})));
  return Build(config, std::move(model));
}

absl::StatusOr<std::shared_ptr<const TossSpec>> TossSpec::CreateFromCompiled(
    const LoadedConfig& config, const std::string& model_mjb) {
  ASSIGN_OR_RETURN(MjModelPtr model, LoadModelCompiled(model_mjb));
  return Build(config, std::move(model));
}

absl::StatusOr<std::shared_ptr<const TossSpec>> TossSpec::Build(const LoadedConfig& config,
                                                                MjModelPtr model) {
  std::shared_ptr<TossSpec> spec(new TossSpec(config, std::move(model)));
  RETURN_IF_ERROR(spec->Resolve());
  spec->SetFingerprint(config.run.toss().SerializeAsString());
  return std::shared_ptr<const TossSpec>(std::move(spec));
}

std::vector<std::string> TossSpec::outcome_names() const {
  std::vector<std::string> names = CommonOutcomeNames();
  for (const char* name : kOutcomeNames) names.push_back(name);
  return names;
}

int TossSpec::obs_dim() const {
  return toss().task() == config::THROW ? kTossThrowObs : kTossCatchObs;
}

std::unique_ptr<Env> TossSpec::NewEnv(Rng rng) const {
  auto self = std::static_pointer_cast<const TossSpec>(shared_from_this());
  if (in_loop()) return std::make_unique<TossLoopEnv>(std::move(self), rng);
  return std::make_unique<TossTaskEnv>(std::move(self), rng);
}

absl::Status TossSpec::ResolveLoop() {
  if (!in_loop()) return absl::OkStatus();
  const config::TossLoopConfig& loop = toss().loop();
  const SourceLocator where = locator().Nested({{"loop"}});
  for (const std::string& text : loop.pattern()) {
    absl::StatusOr<Siteswap> parsed = Siteswap::Parse(text);
    if (!parsed.ok() || parsed->balls() < 1 || parsed->balls() > kTossBalls) {
      return absl::InvalidArgumentError(absl::StrCat(
          where.Where({{"pattern"}}), ": '", text, "': ",
          parsed.ok() ? absl::StrCat(parsed->balls(), " balls; the toss model juggles 1 to ",
                                     kTossBalls)
                      : std::string(parsed.status().message())));
    }
    const Siteswap& pattern = *parsed;
    // The right hand throws on even beats; over two periods every throw comes from both hands.
    bool has_segment = false;
    for (int beat = 0; beat < 2 * pattern.period(); ++beat) {
      const int v = pattern.throws()[beat % pattern.period()];
      if (ComputeThrowTiming(v, beat, timing_).kind != ThrowKind::kToss) continue;
      const bool right_throws = beat % 2 == 0, right_catches = (beat + v) % 2 == 0;
      has_segment |= toss().task() == config::THROW ? right_throws : right_catches;
    }
    if (!has_segment) {
      return absl::InvalidArgumentError(absl::StrCat(
          where.Where({{"pattern"}}), ": '", text, "' never gives the right hand a ",
          toss().task() == config::THROW ? "throw" : "catch", " to train on"));
    }
    loop_patterns_.push_back(pattern);
  }
  struct Partner {
    const char* field;
    bool present;
    const config::ExportedPolicy& exported;
    int obs_dim;
    std::optional<EigenPolicy>* out;
  };
  for (const Partner& p :
       {Partner{"catch_policy_file", loop.has_catch_policy(), loop.catch_policy(), kTossCatchObs,
                &loop_catcher_},
        Partner{"throw_policy_file", loop.has_throw_policy(), loop.throw_policy(), kTossThrowObs,
                &loop_thrower_}}) {
    if (!p.present) continue;  // the base controllers stand in (PrepareLoop checked)
    if (p.exported.obs_dim() != p.obs_dim || p.exported.act_dim() != kTossJoints) {
      return absl::InvalidArgumentError(absl::StrCat(
          where.Where({{p.field}}), ": the policy (", p.exported.source(), ") has ",
          p.exported.obs_dim(), " observations and ", p.exported.act_dim(), " actions; this partner needs ",
          p.obs_dim, " and ", kTossJoints, " (is it the other task's policy?)"));
    }
    absl::StatusOr<EigenPolicy> policy = PolicyFromExport(p.exported);
    if (!policy.ok()) {
      return absl::InvalidArgumentError(
          absl::StrCat(where.Where({{p.field}}), ": ", policy.status().message()));
    }
    p.out->emplace(*std::move(policy));
  }
  return absl::OkStatus();
}

absl::Status TossSpec::Resolve() {
  const std::string where = locator().Where({{"model_file"}});
  auto bad_model = [&](const std::string& what) {
    return absl::InvalidArgumentError(absl::StrCat(where, ": ", what));
  };
  if (std::abs(model_->opt.timestep - 0.01) > 1e-12) {
    return bad_model(absl::StrCat("the toss model's timestep must be 0.01 s (paper Table 1), not ",
                                  model_->opt.timestep));
  }
  for (int h = 0; h < 2; ++h) {
    for (int j = 0; j < kTossJoints; ++j) {
      const int id = mj_name2id(model_.get(), mjOBJ_JOINT, kArmJointNames[h][j]);
      if (id < 0 || model_->jnt_type[id] != mjJNT_HINGE) {
        return bad_model(absl::StrCat("needs a hinge joint '", kArmJointNames[h][j], "'"));
      }
      arms_[h].qpos[j] = model_->jnt_qposadr[id];
      arms_[h].dof[j] = model_->jnt_dofadr[id];
      model_->dof_damping[arms_[h].dof[j]] = toss().kd();  // kd, implicit in Euler
    }
    arms_[h].palm_site = mj_name2id(model_.get(), mjOBJ_SITE, kPalmNames[h]);
    if (arms_[h].palm_site < 0) return bad_model(absl::StrCat("needs a site '", kPalmNames[h], "'"));
  }
  for (int b = 0; b < kTossBalls; ++b) {
    const int jx = mj_name2id(model_.get(), mjOBJ_JOINT, absl::StrCat("ball", b, "_x").c_str());
    const int jz = mj_name2id(model_.get(), mjOBJ_JOINT, absl::StrCat("ball", b, "_z").c_str());
    if (jx < 0 || jz < 0 || model_->jnt_type[jx] != mjJNT_SLIDE || model_->jnt_type[jz] != mjJNT_SLIDE) {
      return bad_model(absl::StrCat("needs slide joints 'ball", b, "_x' and 'ball", b, "_z'"));
    }
    TossBallJoints& ball = balls_[b];
    ball.qpos_x = model_->jnt_qposadr[jx];
    ball.qpos_z = model_->jnt_qposadr[jz];
    ball.dof_x = model_->jnt_dofadr[jx];
    ball.dof_z = model_->jnt_dofadr[jz];
    const int body = model_->jnt_bodyid[jx];
    ball.origin_x = model_->body_pos[3 * body];
    ball.origin_z = model_->body_pos[3 * body + 2];
  }

  // Home pose: two-link inverse kinematics of the right arm (wrist straight, elbow out) that
  // puts the palm at (hand_x, hand_z), checked by MuJoCo's forward kinematics.
  MjDataPtr data(mj_makeData(model_.get()));
  mjData* d = data.get();  // freed on every return
  mj_kinematics(model_.get(), d);
  const TossArmJoints& right = arms_[0];
  const int shoulder = mj_name2id(model_.get(), mjOBJ_JOINT, "right_shoulder");
  const int elbow = mj_name2id(model_.get(), mjOBJ_JOINT, "right_elbow");
  const double sx = d->xanchor[3 * shoulder], sz = d->xanchor[3 * shoulder + 2];
  const double ex = d->xanchor[3 * elbow], ez = d->xanchor[3 * elbow + 2];
  const double px = d->site_xpos[3 * right.palm_site], pz = d->site_xpos[3 * right.palm_site + 2];
  const double l1 = std::hypot(ex - sx, ez - sz), l2 = std::hypot(px - ex, pz - ez);
  const double dx = toss().hand_x() - sx, dz = toss().hand_z() - sz, dist = std::hypot(dx, dz);
  const double cos_elbow = (dist * dist - l1 * l1 - l2 * l2) / (2 * l1 * l2);
  if (!(std::abs(cos_elbow) < 0.999)) {
    return absl::InvalidArgumentError(absl::StrCat(
        locator().Where({{"hand_x"}}), ": the home point (", toss().hand_x(), ", ",
        toss().hand_z(), ") is out of the arm's reach (", l1, " + ", l2, " m from the shoulder)"));
  }
  const double target_angle = std::atan2(-dx, -dz);
  double best_elbow_x = 1e9;
  for (double sign : {1.0, -1.0}) {
    const double qe = sign * std::acos(cos_elbow);
    const double qs = target_angle - std::atan2(l2 * std::sin(qe), l1 + l2 * std::cos(qe));
    const double elbow_x = sx + l1 * LinkX(qs);
    if (elbow_x < best_elbow_x) {  // the right arm's elbow points out (−x)
      best_elbow_x = elbow_x;
      home_ = {0.0, qs, qe, 0.0};
    }
  }
  for (int j = 0; j < kTossJoints; ++j) {
    d->qpos[arms_[0].qpos[j]] = home_[j];
    d->qpos[arms_[1].qpos[j]] = -home_[j];
  }
  mj_kinematics(model_.get(), d);
  const double err = std::hypot(d->site_xpos[3 * right.palm_site] - toss().hand_x(),
                                d->site_xpos[3 * right.palm_site + 2] - toss().hand_z());
  const double mirror_err =
      std::hypot(d->site_xpos[3 * arms_[1].palm_site] + toss().hand_x(),
                 d->site_xpos[3 * arms_[1].palm_site + 2] - toss().hand_z());
  if (err > 1e-6 || mirror_err > 1e-6) {
    return bad_model(absl::StrCat("the arms are not mirror images with straight wrists at qpos 0 "
                                  "(home palm error ", err, " m, mirrored ", mirror_err, " m)"));
  }
  timing_.hand_period_s = toss().hand_period_s();
  timing_.dwell_ratio = toss().dwell_ratio();
  timing_.hand_separation_m = 2 * std::abs(toss().hand_x());
  timing_.gravity = -model_->opt.gravity[2];
  return ResolveLoop();
}

}  // namespace juggle::toss

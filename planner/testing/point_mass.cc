#include "planner/testing/point_mass.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "common/check.h"
#include "common/outcome.h"

namespace juggle::planner::testing {
namespace {

constexpr char kModel[] = R"(
<mujoco>
  <option timestep="0.005" gravity="0 0 0"/>
  <worldbody>
    <body name="mass">
      <joint name="x" type="slide" axis="1 0 0" damping="0.2"/>
      <joint name="y" type="slide" axis="0 1 0" damping="0.2"/>
      <geom type="sphere" size="0.05" mass="1" contype="0" conaffinity="0"/>
    </body>
  </worldbody>
  <actuator>
    <motor joint="x" gear="1" ctrllimited="true" ctrlrange="-1 1"/>
    <motor joint="y" gear="1" ctrllimited="true" ctrlrange="-1 1"/>
  </actuator>
</mujoco>)";

MjModelPtr Compile() {
  mjVFS vfs;
  mj_defaultVFS(&vfs);
  const size_t size = std::strlen(kModel);
  mj_makeEmptyFileVFS(&vfs, "point_mass.xml", static_cast<int>(size));
  std::memcpy(vfs.filedata[mj_findFileVFS(&vfs, "point_mass.xml")], kModel, size);
  char error[512] = "";
  MjModelPtr m(mj_loadXML("point_mass.xml", &vfs, error, sizeof(error)));
  mj_deleteVFS(&vfs);
  JUGGLE_CHECK(m != nullptr, error);
  return m;
}

class PointMassSnapshot final : public EnvSnapshot {
 public:
  std::string family() const override { return "point_mass"; }
  int steps = 0;
};

class PointMassEnv final : public Env {
 public:
  explicit PointMassEnv(std::shared_ptr<const PointMassSpec> spec)
      : spec_(std::move(spec)), data_(mj_makeData(spec_->model())) {}

  void Reset(const AdaptiveWalk&) override {
    mj_resetData(spec_->model(), data_.get());
    mj_forward(spec_->model(), data_.get());
    steps_ = 0;
  }
  StepResult Step(const float* action, const AdaptiveWalk&) override {
    for (int i = 0; i < 2; ++i) data_->ctrl[i] = std::clamp(action[i], -1.0f, 1.0f);
    for (int k = 0; k < PointMassSpec::kSubsteps; ++k) mj_step(spec_->model(), data_.get());
    ++steps_;
    StepResult r;
    if (steps_ >= spec_->max_steps()) r.outcome = Outcome::kTimeLimit;
    return r;
  }
  void WriteObservation(float* obs) const override {
    for (int i = 0; i < 2; ++i) {
      obs[i] = static_cast<float>(data_->qpos[i]);
      obs[2 + i] = static_cast<float>(data_->qvel[i]);
    }
  }
  int steps() const override { return steps_; }
  int completions() const override { return 0; }
  mjData* data() override { return data_.get(); }
  const mjData* data() const override { return data_.get(); }
  std::unique_ptr<EnvSnapshot> Snapshot() const override {
    auto s = std::make_unique<PointMassSnapshot>();
    s->spec_fingerprint = spec_->fingerprint();
    s->physics.Save(spec_->model(), data_.get());
    s->steps = steps_;
    return s;
  }
  absl::Status Restore(const EnvSnapshot& snapshot) override {
    if (absl::Status s = CheckSnapshotMatches(snapshot, "point_mass", spec_->fingerprint());
        !s.ok()) {
      return s;
    }
    const auto& s = static_cast<const PointMassSnapshot&>(snapshot);
    s.physics.Restore(data_.get());
    steps_ = s.steps;
    return absl::OkStatus();
  }

 private:
  std::shared_ptr<const PointMassSpec> spec_;
  MjDataPtr data_;
  int steps_ = 0;
};

// Distance² to the target per step, effort, terminal distance² and speed².
class PointMassScorer final : public RolloutScorer {
 public:
  explicit PointMassScorer(const PointMassTaskSettings& s) : s_(s) {}
  void Begin(const Env&) override {}
  void AfterStep(const Env& env, const float* action, const StepResult&) override {
    distance_ += Distance2(env);
    effort_ += s_.effort * 0.5 * (action[0] * action[0] + action[1] * action[1]);
  }
  double Finish(const Env& env) override {
    const double* v = env.data()->qvel;
    terminal_ = s_.terminal * (Distance2(env) + 0.1 * (v[0] * v[0] + v[1] * v[1]));
    return partial() + terminal_;
  }
  double partial() const override { return distance_ + effort_; }
  std::vector<double> terms() const override { return {distance_, effort_, terminal_}; }

 private:
  double Distance2(const Env& env) const {
    const double* q = env.data()->qpos;
    return std::pow(q[0] - s_.target[0], 2) + std::pow(q[1] - s_.target[1], 2);
  }
  const PointMassTaskSettings& s_;
  double distance_ = 0, effort_ = 0, terminal_ = 0;
};

}  // namespace

PointMassSpec::PointMassSpec(MjModelPtr model, int max_steps)
    : model_(std::move(model)), max_steps_(max_steps) {
  SetFingerprint("point_mass");
}

std::shared_ptr<const PointMassSpec> PointMassSpec::Create(int max_steps) {
  return std::shared_ptr<const PointMassSpec>(new PointMassSpec(Compile(), max_steps));
}

std::vector<std::string> PointMassSpec::outcome_names() const { return CommonOutcomeNames(); }

std::unique_ptr<Env> PointMassSpec::NewEnv(Rng) const {
  return std::make_unique<PointMassEnv>(
      std::static_pointer_cast<const PointMassSpec>(shared_from_this()));
}

PointMassTask::PointMassTask(const PointMassTaskSettings& settings)
    : settings_(settings),
      // From an origin up to knot_steps − 1 past knot 0 to the horizon's end, plus one.
      knots_((settings.knot_steps + settings.horizon - 2) / settings.knot_steps + 2) {
  space_.lower.assign(2 * knots_, -1.0);
  space_.upper.assign(2 * knots_, 1.0);
  space_.sigma.assign(2 * knots_, settings.sigma);
  rescue_space_ = space_;
  for (double& s : rescue_space_.sigma) s = std::min(4 * s, 2.0);
}

std::vector<double> PointMassTask::Shift(const std::vector<double>& theta, int grid_steps,
                                         int) const {
  const int moved = std::max(grid_steps / settings_.knot_steps, 0);
  std::vector<double> out(theta.size());
  for (int k = 0; k < knots_; ++k) {
    const int from = std::min(k + moved, knots_ - 1);
    std::copy_n(theta.begin() + 2 * from, 2, out.begin() + 2 * k);
  }
  return out;
}

void PointMassTask::Action(const Env&, const double* theta, PlanClock clock, const double* prior,
                           float* action) const {
  const int k = std::clamp(clock.step / settings_.knot_steps, 0, knots_ - 1);
  const double f = k == knots_ - 1 ? 0.0
                                   : static_cast<double>(clock.step - k * settings_.knot_steps) /
                                         settings_.knot_steps;
  for (int i = 0; i < 2; ++i) {
    const double next = theta[2 * std::min(k + 1, knots_ - 1) + i];
    const double a = (1 - f) * theta[2 * k + i] + f * next + (prior != nullptr ? prior[i] : 0.0);
    action[i] = static_cast<float>(std::clamp(a, -1.0, 1.0));
  }
}

std::unique_ptr<RolloutScorer> PointMassTask::NewScorer() const {
  return std::make_unique<PointMassScorer>(settings_);
}

}  // namespace juggle::planner::testing

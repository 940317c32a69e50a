#include "planner/toss/task.h"

#include <algorithm>
#include <cmath>

#include "absl/strings/str_cat.h"
#include "common/check.h"
#include "envs/toss/outcomes.h"
#include "envs/toss/task_env.h"

namespace juggle::planner {
namespace {

using toss::TossTaskEnv;

// The toss model's control step (TossSpec refuses another timestep).
constexpr double kTossDt = 0.01;

const TossTaskEnv& AsTaskEnv(const Env& env) {
  const auto* task = dynamic_cast<const TossTaskEnv*>(&env);
  JUGGLE_CHECK(task != nullptr, "the toss planning task plans the single-arm task env only");
  return *task;
}

// The latest release beat of a THROW episode (TossTaskEnv::ResetThrow), in control steps.
int LatestReleaseStep(const config::TossConfig& t) {
  const double latest = t.dwell_ratio() * t.hand_period_s() + t.catch_timing_jitter_s();
  return std::max(1, static_cast<int>(std::lround(latest / kTossDt)));
}

// Scores one rollout of a throw: effort every step, the release's errors at the release beat.
class TossThrowScorer final : public RolloutScorer {
 public:
  TossThrowScorer(const config::TossPlanning& s, int horizon) : s_(s), horizon_(horizon) {}

  void Begin(const Env& env) override {
    const toss::TossWorld& world = AsTaskEnv(env).world();
    // The acting hand holds the task's ball (ball 0) until the release.
    hand_ = world.mode(0) == toss::BallMode::kHeld ? world.holder(0) : toss::Hand::kRight;
  }

  void AfterStep(const Env& env, const float*, const StepResult& r) override {
    const TossTaskEnv& task = AsTaskEnv(env);
    ++steps_;
    effort_ += s_.effort() * task.world().Effort(hand_);
    if (r.outcome == toss::kReleased) {
      released_ = true;
      velocity_error_ = task.release_velocity_error();
      position_error_ = task.release_position_error();
      velocity_ = s_.release_velocity() * std::pow(velocity_error_ / s_.velocity_scale(), 2);
      position_ = s_.release_position() * std::pow(position_error_ / s_.position_scale(), 2);
    } else if (r.outcome != Outcome::kRunning) {
      // Diverged, or the episode's step limit before the beat: a later end is less bad.
      failure_ = s_.failure() * (2.0 - static_cast<double>(steps_) / horizon_);
    }
  }

  double Finish(const Env&) override {
    // A horizon that ends before the beat cannot score the throw (ValidateTossTask refuses
    // horizons that cannot reach it from an episode's first state).
    if (!released_ && failure_ == 0) failure_ = s_.failure();
    return partial();
  }

  double partial() const override { return velocity_ + position_ + effort_ + failure_; }

  std::vector<double> first_outcome() const override {
    if (!released_) return {};
    return {velocity_error_, position_error_};
  }

  std::vector<double> terms() const override { return {velocity_, position_, effort_, failure_}; }

 private:
  const config::TossPlanning& s_;
  int horizon_;
  toss::Hand hand_ = toss::Hand::kRight;
  int steps_ = 0;
  bool released_ = false;
  double velocity_error_ = 0, position_error_ = 0;
  double velocity_ = 0, position_ = 0, effort_ = 0, failure_ = 0;
};

}  // namespace

TossThrowTask::TossThrowTask(std::shared_ptr<const toss::TossSpec> spec,
                             const config::PlannerConfig& config)
    : spec_(std::move(spec)),
      settings_(config.toss()),
      horizon_(config.horizon_steps()),
      // From an origin up to knot_steps − 1 past knot 0 to the horizon's end, plus one.
      knots_((settings_.knot_steps() + horizon_ - 2) / settings_.knot_steps() + 2) {
  space_.lower.assign(size_t(kJoints) * knots_, -settings_.limit());
  space_.upper.assign(size_t(kJoints) * knots_, settings_.limit());
  space_.sigma.assign(size_t(kJoints) * knots_, settings_.sigma());
  rescue_space_ = space_;
  for (double& s : rescue_space_.sigma) {
    s = std::min(s * config.rescue().sigma_scale(), 2 * settings_.limit());
  }
}

int TossThrowTask::KnotAtOrBefore(int step) const {
  return step / settings_.knot_steps() * settings_.knot_steps();
}

std::vector<double> TossThrowTask::Shift(const std::vector<double>& theta, int grid_steps,
                                         int) const {
  // Knot k of the shifted plan is knot k + moved of the old one; the last knot repeats.
  const int moved = std::max(grid_steps / settings_.knot_steps(), 0);
  std::vector<double> out(theta.size());
  for (int k = 0; k < knots_; ++k) {
    const int from = std::min(k + moved, knots_ - 1);
    std::copy_n(theta.begin() + size_t(kJoints) * from, kJoints, out.begin() + size_t(kJoints) * k);
  }
  return out;
}

void TossThrowTask::Action(const Env&, const double* theta, PlanClock clock, const double* prior,
                           float* action) const {
  const int h = settings_.knot_steps();
  const int k = std::clamp(clock.step / h, 0, knots_ - 1);
  const double f = k == knots_ - 1 ? 0.0 : static_cast<double>(clock.step - k * h) / h;
  const double* a = theta + size_t(kJoints) * k;
  const double* b = theta + size_t(kJoints) * std::min(k + 1, knots_ - 1);
  for (int i = 0; i < toss::kTossJoints; ++i) {
    double value = prior != nullptr ? prior[i] : 0.0;
    const int j = i - kFirstJoint;
    if (j >= 0 && j < kJoints) value += (1 - f) * a[j] + f * b[j];
    action[i] = static_cast<float>(std::clamp(value, -1.0, 1.0));
  }
}

std::unique_ptr<RolloutScorer> TossThrowTask::NewScorer() const {
  return std::make_unique<TossThrowScorer>(settings_, horizon_);
}

std::vector<std::string> TossThrowTask::term_names() const {
  return {"release_velocity", "release_position", "effort", "failure"};
}

std::vector<std::string> TossThrowTask::outcome_names() const {
  return {"velocity_error_m_s", "position_error_m"};
}

absl::Status ValidateTossTask(const LoadedConfig& config) {
  const config::PlannerConfig& p = config.run.planner();
  const config::TossConfig& t = config.run.toss();
  if (t.task() != config::THROW) {
    return absl::InvalidArgumentError(absl::StrCat(
        config.root.Where({{"toss"}, {"task"}}), ": the toss planning task plans the THROW "
        "task (one throw per episode), not ", config::TossTask_Name(t.task())));
  }
  if (t.has_loop()) {
    return absl::InvalidArgumentError(absl::StrCat(
        config.root.Where({{"toss"}, {"loop"}}), ": the toss planning task plans the single-arm "
        "THROW task; the in-loop env's episodes are segments of a two-arm run, not one throw"));
  }
  const int latest = LatestReleaseStep(t);
  if (p.horizon_steps() < latest) {
    return absl::InvalidArgumentError(absl::StrCat(
        config.root.Where({{"planner"}, {"horizon_steps"}}), ": a horizon of ", p.horizon_steps(),
        " control steps cannot reach the latest release beat, ", latest,
        " steps after an episode's start (toss.dwell_ratio × hand_period_s + "
        "catch_timing_jitter_s)"));
  }
  if (p.horizon_steps() > t.max_episode_steps()) {
    return absl::InvalidArgumentError(absl::StrCat(
        config.root.Where({{"planner"}, {"horizon_steps"}}), ": a horizon of ", p.horizon_steps(),
        " control steps is longer than the episode (toss.max_episode_steps ",
        t.max_episode_steps(), ")"));
  }
  return absl::OkStatus();
}

}  // namespace juggle::planner

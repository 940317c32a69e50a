#include "planner/football/kick_task.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "envs/football/env.h"
#include "envs/football/kick_motion.h"
#include "envs/football/metrics.h"
#include "envs/football/outcomes.h"
#include "envs/geom_extent.h"
#include "planner/planner_config.h"
#include "planner/pose_action.h"

namespace juggle::planner {
namespace {

using football::AsFootballEnv;
using football::FootballEnv;
using football::KickAdjust;

// Steps a cut window may run on (1/6 s at 50 Hz is 9 steps).
constexpr int kKickRunOnSteps = 10;

double Norm3(const double* v) { return std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]); }

// How far the kicking foot's centre is from the ball's surface, less the foot's longest half
// extent (its bounds', envs/geom_extent.h; m; ≤ 0 roughly at a touch).
double FootGap(const FootballEnv& env) {
  const football::FootballSpec& spec = env.spec();
  const mjData* d = env.data();
  double foot[3];
  GeomBoundsCentre(spec.kick_foot_bounds(), spec.model(), d, foot);
  const double* ball = d->qpos + spec.ball().qpos;
  const double diff[3] = {ball[0] - foot[0], ball[1] - foot[1], ball[2] - foot[2]};
  return Norm3(diff) - spec.ball().radius - spec.kick_foot_bounds().longest();
}

class KickScorer final : public RolloutScorer {
 public:
  // `first_step`: the rollout's steps before Begin (a fall is weighed by when in the rollout it
  // comes).
  KickScorer(const config::FootballPlanning& s, int horizon, int first_step = 0)
      : s_(s), horizon_(horizon), steps_(first_step) {}

  void Begin(const Env& env) override {
    const FootballEnv& e = AsFootballEnv(env);
    window_done_at_begin_ = e.state().window_done;
    touched_at_begin_ = e.state().touch_body >= 0;
    closest_gap_ = FootGap(e);
  }

  void AfterStep(const Env& env, const float*, const StepResult& r) override {
    const FootballEnv& e = AsFootballEnv(env);
    ++steps_;
    if (!touched_at_begin_) closest_gap_ = std::min(closest_gap_, FootGap(e));
    if (r.outcome == football::kWrongTouch) {
      miss_ = 2 * s_.miss();
    } else if (r.outcome == football::kFell || r.outcome == Outcome::kDiverged) {
      failure_ = s_.failure() * (2.0 - static_cast<double>(std::min(steps_, horizon_)) / horizon_);
    }
    // The window's score so far, so that first_outcome() holds it before Finish too (the driver
    // reads it first: planner/receding_horizon.cc).
    ScoreWindow(e.state());
  }

  double Finish(const Env& env) override {
    const FootballEnv& e = AsFootballEnv(env);
    const football::FootballEnvState& st = e.state();
    ScoreWindow(st);
    if (scored_) {
      const double p = s_.deviation_power();
      direction_ = s_.direction() * std::pow(kdd_ / s_.direction_scale_deg(), p);
      speed_term_ = s_.speed() * std::pow(ksd_ / s_.speed_scale_mps(), p);
    }
    if (!touched_at_begin_ && st.touch_body < 0 && miss_ == 0 && failure_ == 0) {
      const football::KickTimes t = football::KickTimesOf(e.spec().football().motion(), {});
      if (e.kick_time_s() >= t.recover) miss_ = s_.miss() * (1 + std::max(0.0, closest_gap_) / 0.05);
    }
    const mjData* d = e.data();
    const double upright[4] = {M_SQRT1_2, M_SQRT1_2, 0, 0};
    const double dot = mju_dot(d->qpos + 3, upright, 4);
    upright_ = s_.upright() * std::pow(std::max(0.0, 1 - dot * dot) / 0.01, 2);
    return partial();
  }

  double partial() const override { return direction_ + speed_term_ + miss_ + failure_ + upright_; }

  // The kick's outcome over its window (the samples so far, all of them once it is done) when
  // this rollout saw the window open; its cost terms are set by Finish only (partial() stays a
  // lower bound of the total).
  void ScoreWindow(const football::FootballEnvState& st) {
    if (window_done_at_begin_ || !st.kick.touched) return;
    const football::KickScore k =
        st.window_done ? st.score : football::ScoreKick(st.kick, football::kKickWindowS);
    if (!k.success) return;
    scored_ = true;
    kdd_ = k.direction_deviation_deg;
    ksd_ = k.speed_deviation_mps;
    double speed = 0;
    for (const football::BallVelocitySample& v : st.kick.after_touch) speed += Norm3(v.velocity);
    speed_ = speed / std::max<size_t>(1, st.kick.after_touch.size());
    errors_ = football::SignedKickErrors(st.kick, football::kKickWindowS);
  }

  bool RunsOn(const Env& env) const override {
    const football::FootballEnvState& st = AsFootballEnv(env).state();
    return st.kick.touched && !st.window_done;
  }

  std::vector<double> first_outcome() const override {
    if (!scored_) return {};
    return {kdd_, ksd_, speed_, errors_.azimuth_deg, errors_.elevation_deg, errors_.speed_mps};
  }

  std::vector<double> terms() const override {
    return {direction_, speed_term_, miss_, failure_, upright_};
  }

 private:
  const config::FootballPlanning& s_;
  int horizon_;
  int steps_ = 0;
  bool window_done_at_begin_ = false, touched_at_begin_ = false, scored_ = false;
  double closest_gap_ = std::numeric_limits<double>::infinity();
  double kdd_ = 0, ksd_ = 0, speed_ = 0;
  football::KickErrors errors_;
  double direction_ = 0, speed_term_ = 0, miss_ = 0, failure_ = 0, upright_ = 0;
};

}  // namespace

FootballKickTask::FootballKickTask(std::shared_ptr<const football::FootballSpec> spec,
                                   const config::PlannerConfig& config)
    : spec_(std::move(spec)),
      settings_(config.football()),
      layout_(MakeSoccerPlanLayout(config, settings_.kick())),
      space_(MakeSoccerSearchSpace(layout_, config, settings_.kick())) {
  rescue_space_ = space_;
  for (int v = 0; v < rescue_space_.dim(); ++v) {
    rescue_space_.sigma[v] = std::min(rescue_space_.sigma[v] * config.rescue().sigma_scale(),
                                      rescue_space_.upper[v] - rescue_space_.lower[v]);
  }
}

int FootballKickTask::max_run_on_steps() const { return kKickRunOnSteps; }

int FootballKickTask::KnotAtOrBefore(int step) const {
  return planner::KnotAtOrBefore(layout_, step);
}

std::vector<double> FootballKickTask::Shift(const std::vector<double>& theta, int grid_steps,
                                            int) const {
  // One kick per episode: its set stays; the body knots move with the grid.
  const int knots = layout_.knot_steps > 0 ? grid_steps / layout_.knot_steps : 0;
  return ShiftSoccerPlan(layout_, theta, knots, 0);
}

void FootballKickTask::Action(const Env& env, const double* theta, PlanClock clock,
                              const double* prior, float* action) const {
  const FootballEnv& e = AsFootballEnv(env);
  double a[football::kNumActions] = {0};
  if (prior != nullptr) std::copy_n(prior, football::kNumActions, a);
  if (layout_.kick_sets > 0) {
    const double* kick = theta + layout_.kick(0);
    const KickAdjust adjust{kick[0], kick[1], kick[2], kick[3], kick[4]};
    humanoid::CharacterPose from, to;
    const double t = e.kick_time_s();
    football::KickReferencePose(*spec_, t, {}, &from);
    football::KickReferencePose(*spec_, t, adjust, &to);
    AddPoseChangeAction(spec_->joints(), from, to, spec_->football().action_torque(), a);
  }
  if (layout_.body_knots > 0) {
    for (int i = 0; i < layout_.knot_size(); ++i) {
      a[layout_.body_actions[i]] += BodySplineValue(layout_, theta, clock.step, i);
    }
  }
  for (int i = 0; i < football::kNumActions; ++i) {
    action[i] = static_cast<float>(std::clamp(a[i], -1.0, 1.0));
  }
}

std::unique_ptr<RolloutScorer> FootballKickTask::NewScorer() const {
  return std::make_unique<KickScorer>(settings_, layout_.horizon);
}

std::unique_ptr<RolloutScorer> FootballKickTask::NewScorerFrom(int first_step) const {
  return std::make_unique<KickScorer>(settings_, layout_.horizon, first_step);
}

std::vector<std::string> FootballKickTask::term_names() const {
  return {"direction", "speed", "miss", "failure", "upright"};
}

std::vector<std::string> FootballKickTask::outcome_names() const {
  return {"kdd_deg", "ksd_mps", "speed_mps", "azimuth_err_deg", "elevation_err_deg",
          "speed_err_mps"};
}

std::optional<VariableBlock> FootballKickTask::RefineBlock(const Env& env) const {
  // The kick set while the ball is still to be kicked (after the touch nothing it moves counts).
  if (layout_.kick_sets == 0 || AsFootballEnv(env).state().kick.touched) return std::nullopt;
  return VariableBlock{layout_.kick(0), KickRefineSteps()};
}

bool FootballKickTask::Residuals(const std::vector<double>& outcome, double* out) const {
  if (outcome.size() != 6) return false;
  // The signed errors in the cost's units and weights: their squares add up as its terms do.
  const double direction = std::sqrt(settings_.direction()) / settings_.direction_scale_deg();
  out[0] = direction * outcome[3];
  out[1] = direction * outcome[4];
  out[2] = std::sqrt(settings_.speed()) / settings_.speed_scale_mps() * outcome[5];
  return true;
}

const float* FootballKickTask::AppliedAction(const Env& env) const {
  return AsFootballEnv(env).state().previous_action.data();
}

std::string FootballKickTask::DescribeDecision(const std::vector<double>& d,
                                               const std::vector<double>& outcome) const {
  std::string out = FormatKickVariables(d);
  if (outcome.size() >= 3) {
    absl::StrAppendFormat(&out, "  kick: kdd %.2f deg, ksd %.2f m/s, speed %.2f m/s", outcome[0],
                          outcome[1], outcome[2]);
  }
  return out;
}

absl::Status ValidateFootballTask(const LoadedConfig& config) {
  const config::PlannerConfig& p = config.run.planner();
  auto where = [&](const char* field) { return config.root.Where({{"planner"}, {field}}); };
  const int episode = config.run.football().max_episode_steps();
  if (p.horizon_steps() > episode) {
    return absl::InvalidArgumentError(absl::StrCat(
        where("horizon_steps"), ": a horizon of ", p.horizon_steps(),
        " control steps is longer than the episode (football.max_episode_steps ", episode, ")"));
  }
  const config::SecondTouch& second = p.football().second_touch();
  if (second.enabled() && config.run.football().task() != config::TRAP_KICK) {
    return absl::InvalidArgumentError(absl::StrCat(
        config.root.Where({{"planner"}, {"football"}, {"second_touch"}, {"enabled"}}),
        ": a second touch follows a trap into a kick; this config's football.task is ",
        config::FootballTask_Name(config.run.football().task()), ", not TRAP_KICK"));
  }
  if (second.enabled() && second.earliest_s() > second.latest_s()) {
    return absl::InvalidArgumentError(absl::StrCat(
        config.root.Where({{"planner"}, {"football"}, {"second_touch"}, {"earliest_s"}}), ": ",
        second.earliest_s(), " s is after latest_s (", second.latest_s(), " s)"));
  }
  const config::TrapPlanning& trap = p.football().trap();
  // The trap's settings and each part's (TrapPlanning.foot, ...), by their field names.
  const std::pair<const char*, const config::TrapPlanning*> parts[] = {
      {nullptr, &trap},         {"foot", &trap.foot()}, {"lower_leg", &trap.lower_leg()},
      {"torso", &trap.torso()}, {"head", &trap.head()}, {"ground", &trap.ground()}};
  for (const auto& [name, part] : parts) {
    FieldPath path = {{"planner"}, {"football"}, {"trap"}};
    if (name != nullptr) path.push_back({name});
    if (name != nullptr && part->ByteSizeLong() > 0 &&
        config.run.football().task() != config::TRAP &&
        config.run.football().task() != config::TRAP_KICK) {
      return absl::InvalidArgumentError(absl::StrCat(
          config.root.Where(path),
          ": a part's own trap settings are for the TRAP and TRAP_KICK tasks; this config's "
          "football.task is ",
          config::FootballTask_Name(config.run.football().task())));
    }
    if (name != nullptr && (part->has_foot() || part->has_lower_leg() || part->has_torso() ||
                            part->has_head() || part->has_ground())) {
      return absl::InvalidArgumentError(absl::StrCat(
          config.root.Where(path), ": a part's settings cannot hold part settings of their own"));
    }
    if ((name == nullptr || part->has_keep_margin_m()) &&
        part->keep_margin_m() >= config.run.football().trap().reach_m()) {
      path.push_back({"keep_margin_m"});
      return absl::InvalidArgumentError(absl::StrCat(
          config.root.Where(path), ": ", part->keep_margin_m(),
          " m leaves no room inside football.trap.reach_m (", config.run.football().trap().reach_m(),
          " m)"));
    }
  }
  if (config.run.football().task() != config::KICK &&
      (p.refine_iterations() > 0 || p.rescue().refine_first() > 0 ||
       p.rescue().refine_after() > 0)) {
    // Only the kick task has residuals (FootballKickTask::Residuals); elsewhere nothing refines.
    const char* field = p.refine_iterations() > 0  ? "refine_iterations"
                        : p.rescue().refine_first() > 0 ? "refine_first"
                                                        : "refine_after";
    FieldPath path = {{"planner"}};
    if (p.refine_iterations() == 0) path.push_back({"rescue"});
    path.push_back({field});
    return absl::InvalidArgumentError(absl::StrCat(
        config.root.Where(path), ": the refinement steps on the kick task's residuals; this "
        "config's football.task is ", config::FootballTask_Name(config.run.football().task()),
        ", which has none: set it to 0"));
  }
  if (config.run.football().task() == config::TRAP) {
    // trap_task.h: the plan is the reach pose alone; knots asked for would be ignored silently.
    if (std::optional<FieldPath> knots = BodyKnotRequest(p)) {
      FieldPath path = {{"planner"}};
      path.insert(path.end(), knots->begin(), knots->end());
      return absl::InvalidArgumentError(absl::StrCat(
          config.root.Where(path), ": the TRAP task's plan is its reach pose, without whole-body "
          "knots (docs/football.md, \"The trap by search\"): set body_knot_steps to 0"));
    }
    return absl::OkStatus();
  }
  // KICK and TRAP_KICK (trap_kick_task.h) plan the kick variables.
  if (absl::StatusOr<std::vector<int>> a = BodyActionIndices(p.body_actions()); !a.ok()) {
    return absl::InvalidArgumentError(absl::StrCat(where("body_actions"), ": ", a.status().message()));
  }
  if (!p.football().kick().enabled()) {
    return absl::InvalidArgumentError(absl::StrCat(
        config.root.Where({{"planner"}, {"football"}, {"kick"}, {"enabled"}}),
        ": the kick task plans the kick variables; they cannot be off"));
  }
  if (p.football().kick().cycles() != 1) {
    return absl::InvalidArgumentError(absl::StrCat(
        config.root.Where({{"planner"}, {"football"}, {"kick"}, {"cycles"}}),
        ": one kick per episode: cycles must be 1"));
  }
  return absl::OkStatus();
}

}  // namespace juggle::planner

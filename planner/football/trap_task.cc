#include "planner/football/trap_task.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "absl/strings/str_format.h"
#include "envs/football/env.h"
#include "envs/football/outcomes.h"
#include "envs/geom_extent.h"
#include "envs/humanoid/pose.h"
#include "planner/football/free_ball.h"
#include "planner/pose_action.h"

namespace juggle::planner {
namespace {

using football::AsFootballEnv;
using football::FootballEnv;
using football::TrapEpisode;

// Steps a horizon may run on to record the relative speed's frames after a touch.
constexpr int kTrapRunOnSteps = football::kRelativeSpeedFrames;
// How far the ball's path is followed past the horizon (s) and how finely.
constexpr double kPathSeconds = 1.0, kPathStep = 0.01;
// The keep term's scale: lost + reach × (metres beyond trap.reach_m − keep_margin_m at the
// trap's end / kKeepScale)².
constexpr double kKeepScale = 0.5;

double Smoothstep(double u) {
  u = std::clamp(u, 0.0, 1.0);
  return u * u * (3 - 2 * u);
}

// The designated part's centre now (its bounds', envs/geom_extent.h).
void PartCentre(const FootballEnv& e, double centre[3]) {
  GeomBoundsCentre(e.spec().trap_bodies().bounds[e.state().trap.part], e.spec().model(), e.data(),
                   centre);
}

// From the part's surface (its centre `part`) to the ball's.
double SurfaceGap(const FootballEnv& e, const double* part, const double* ball) {
  const double d[3] = {ball[0] - part[0], ball[1] - part[1], ball[2] - part[2]};
  return mju_norm3(d) - e.spec().ball().radius -
         e.spec().trap_bodies().bounds[e.state().trap.part].thinnest();
}

// The part's closest approach to the ball's free path from now on, with the part where it is.
double PathGap(const FootballEnv& e) {
  FreeBall ball(e);
  double part[3];
  PartCentre(e, part);
  double best = SurfaceGap(e, part, ball.p);
  for (double t = 0; t < kPathSeconds; t += kPathStep) {
    ball.Step(kPathStep);
    best = std::min(best, SurfaceGap(e, part, ball.p));
  }
  return best;
}

// How far the ball's free path takes it from the root, horizontally (m), by the trap's end
// (settle_s after the first touch; REQUIRES a touch).
double DistanceAtSettle(const FootballEnv& e) {
  const TrapEpisode& t = e.state().trap;
  FreeBall ball(e);
  const double end = t.first_touch_s + e.spec().football().trap().settle_s();
  for (double now = e.data()->time; now < end - 1e-9; now += kPathStep) {
    ball.Step(std::min(kPathStep, end - now));
  }
  return std::hypot(ball.p[0] - e.data()->qpos[0], ball.p[1] - e.data()->qpos[1]);
}

class TrapScorer final : public RolloutScorer {
 public:
  TrapScorer(const config::FootballPlanning& s, const FootballTrapTask& task, int horizon)
      : s_(s), task_(task), horizon_(horizon) {}

  void Begin(const Env& env) override {
    const TrapEpisode& t = AsFootballEnv(env).state().trap;
    p_ = &task_.PlanningFor(t);
    touched_at_begin_ = t.first_body >= 0;
    arms_at_begin_ = t.arms_touched;
    frames_at_begin_ = static_cast<int>(t.attempt.relative_speed_after_touch.size());
  }

  void AfterStep(const Env& env, const float*, const StepResult& r) override {
    const FootballEnv& e = AsFootballEnv(env);
    ++steps_;
    if (!touched_at_begin_ && e.state().trap.first_body < 0) {
      double part[3];
      PartCentre(e, part);
      closest_gap_ = std::min(closest_gap_, SurfaceGap(e, part, e.data()->qpos + e.spec().ball().qpos));
    }
    if (r.outcome == football::kGroundFirst || r.outcome == football::kWrongPart) {
      miss_ = p_->miss() * (1 + std::max(0.0, closest_gap_) / p_->reach_scale_m());
    } else if (r.outcome == football::kFell || r.outcome == Outcome::kDiverged) {
      failure_ = s_.failure() * (2.0 - static_cast<double>(std::min(steps_, horizon_)) / horizon_);
    }
  }

  double Finish(const Env& env) override {
    const FootballEnv& e = AsFootballEnv(env);
    const TrapEpisode& t = e.state().trap;
    const config::TrapPlanning& p = *p_;
    if (t.first_body < 0 && miss_ == 0 && failure_ == 0) {
      const double gap = std::max(0.0, std::min(closest_gap_, PathGap(e)));
      reach_ = p.reach() * std::pow(gap / p.reach_scale_m(), 2);
    }
    const std::vector<double>& speeds = t.attempt.relative_speed_after_touch;
    if (t.first_body >= 0 && t.first_body == e.spec().trap_bodies().body[t.part] &&
        static_cast<int>(speeds.size()) > frames_at_begin_) {
      double sum = 0;
      for (double v : speeds) sum += v;
      scored_ = true;
      relative_ = sum / speeds.size();
      relative_term_ = p.relative_speed() * std::pow(relative_ / p.relative_speed_scale_mps(), 2);
      // Whether the ball will still be within reach when the trap ends.
      const double beyond = (t.settled ? t.end_distance_m : DistanceAtSettle(e)) -
                            (e.spec().football().trap().reach_m() - p.keep_margin_m());
      if (beyond > 0) keep_ = p.lost() + p.reach() * std::pow(beyond / kKeepScale, 2);
    }
    if (t.arms_touched && !arms_at_begin_) handball_ = p.handball();
    const mjData* d = e.data();
    const double upright[4] = {M_SQRT1_2, M_SQRT1_2, 0, 0};
    const double dot = mju_dot(d->qpos + 3, upright, 4);
    upright_ = (p.has_upright() ? p.upright() : s_.upright()) *
               std::pow(std::max(0.0, 1 - dot * dot) / 0.01, 2);
    return partial();
  }

  double partial() const override {
    return reach_ + relative_term_ + keep_ + miss_ + handball_ + failure_ + upright_;
  }

  bool RunsOn(const Env& env) const override {
    const TrapEpisode& t = AsFootballEnv(env).state().trap;
    return t.first_body >= 0 && !t.settled &&
           static_cast<int>(t.attempt.relative_speed_after_touch.size()) <
               football::kRelativeSpeedFrames;
  }

  std::vector<double> first_outcome() const override {
    if (!scored_ || touched_at_begin_) return {};
    return {relative_};
  }

  std::vector<double> terms() const override {
    return {reach_, relative_term_, keep_, miss_, handball_, failure_, upright_};
  }

 private:
  const config::FootballPlanning& s_;
  const FootballTrapTask& task_;
  const config::TrapPlanning* p_ = nullptr;  // the pass's part's (Begin)
  int horizon_;
  int steps_ = 0, frames_at_begin_ = 0;
  bool touched_at_begin_ = false, arms_at_begin_ = false, scored_ = false;
  double closest_gap_ = std::numeric_limits<double>::infinity();
  double relative_ = 0;
  double reach_ = 0, relative_term_ = 0, keep_ = 0, miss_ = 0, handball_ = 0, failure_ = 0;
  double upright_ = 0;
};

}  // namespace

config::TrapPlanning TrapPlanningFor(const config::TrapPlanning& p, config::TrapPart part,
                                     bool ground_pass) {
  config::TrapPlanning out = p;
  out.clear_foot();
  out.clear_lower_leg();
  out.clear_torso();
  out.clear_head();
  out.clear_ground();
  switch (part) {
    case config::FOOT: out.MergeFrom(p.foot()); break;
    case config::LOWER_LEG: out.MergeFrom(p.lower_leg()); break;
    case config::TORSO: out.MergeFrom(p.torso()); break;
    case config::HEAD: out.MergeFrom(p.head()); break;
    default: break;
  }
  if (ground_pass) out.MergeFrom(p.ground());
  return out;
}

ReachRamps ReachRampsOf(const config::TrapPlanning& p) {
  return {p.ramp_s(), p.give_ramp_s() > 0 ? p.give_ramp_s() : p.ramp_s()};
}

double ReachWeight(double reached, double give, double t, const ReachRamps& ramps) {
  return t <= reached ? Smoothstep((t - (reached - ramps.rise_s)) / ramps.rise_s)
                      : 1 - give * Smoothstep((t - reached) / ramps.give_s);
}

void TrapReachPose(const football::FootballSpec& spec, const double* theta, double meet_s, double t,
                   const ReachRamps& ramps, humanoid::CharacterPose* pose, const LegChange& extra,
                   bool squat) {
  *pose = spec.standing_pose();
  const double w = ReachWeight(meet_s + theta[0], theta[8], t, ramps);
  const bool leg = extra.hip != 0 || extra.abduction != 0 || extra.knee != 0 || extra.ankle != 0;
  if (w == 0 && !leg) return;  // before the ramp (or a give of exactly 1 completed)
  const humanoid::Joints& joints = spec.joints();
  // Flexion about z and abduction about x (−x moves the right limb outward), as the kick's; the
  // trunk's lean flexes both hips (with the feet on the turf it tilts the pelvis forward).
  // A squat bends both knees by the knee variable and keeps the shins and thighs at equal and
  // opposite tilts: hips and ankles (toes up, +z) by half of it.
  const double knee = w * theta[3];
  const double half = squat ? knee / 2 : 0;
  const double lean = w * theta[5];
  const double right_hip[3] = {-(w * theta[2] + extra.abduction), 0,
                               w * theta[1] + extra.hip + lean + half};
  humanoid::SetBallJointRotation(joints, humanoid::kRightHip, right_hip, pose);
  const double left_hip[3] = {0, 0, lean + half};
  humanoid::SetBallJointRotation(joints, humanoid::kLeftHip, left_hip, pose);
  humanoid::SetHinge(joints, humanoid::kRightKnee, -(knee + extra.knee), pose);
  const double ankle[3] = {0, 0, w * theta[4] + extra.ankle + half};
  humanoid::SetBallJointRotation(joints, humanoid::kRightAnkle, ankle, pose);
  if (squat) {
    humanoid::SetHinge(joints, humanoid::kLeftKnee, -knee, pose);
    const double left_ankle[3] = {0, 0, half};
    humanoid::SetBallJointRotation(joints, humanoid::kLeftAnkle, left_ankle, pose);
  }
  const double chest[3] = {0, 0, w * theta[6]};
  humanoid::SetBallJointRotation(joints, humanoid::kChest, chest, pose);
  const double neck[3] = {0, 0, w * theta[7]};
  humanoid::SetBallJointRotation(joints, humanoid::kNeck, neck, pose);
}

SearchSpace ReachSpace(double earliest_s, double latest_s, double timing_sigma_s, int angles,
                       double angle_limit, double angle_sigma, double give_max) {
  SearchSpace out;
  out.lower = {earliest_s};
  out.upper = {latest_s};
  out.sigma = {timing_sigma_s};
  for (int v = 0; v < angles; ++v) {
    out.lower.push_back(-angle_limit);
    out.upper.push_back(angle_limit);
    out.sigma.push_back(angle_sigma);
  }
  // The give: the share of the reach taken back after it (a cushion), in [0, give_max].
  out.lower.push_back(0);
  out.upper.push_back(give_max);
  out.sigma.push_back(0.3);
  return out;
}

namespace {

// The regular and the rescue search's space for passes planned with `p`.
SearchSpace ReachSpaceOf(const config::TrapPlanning& p) {
  return ReachSpace(-p.timing_limit_s(), p.timing_limit_s(), p.timing_sigma_s(), kTrapVariables - 2,
                    p.angle_limit(), p.angle_sigma(), p.give_max());
}

}  // namespace

FootballTrapTask::FootballTrapTask(std::shared_ptr<const football::FootballSpec> spec,
                                   const config::PlannerConfig& config)
    : spec_(std::move(spec)), settings_(config.football()), horizon_(config.horizon_steps()) {
  for (int part = 0; part < config::TrapPart_ARRAYSIZE; ++part) {
    by_part_[part] = TrapPlanningFor(settings_.trap(), static_cast<config::TrapPart>(part));
    part_space_[part] = ReachSpaceOf(by_part_[part]);
  }
  ground_ = TrapPlanningFor(settings_.trap(), config::FOOT, /*ground_pass=*/true);
  ground_space_ = ReachSpaceOf(ground_);
}

const config::TrapPlanning& FootballTrapTask::PlanningFor(
    const football::TrapEpisode& episode) const {
  return episode.pass.kind == football::PassKind::kGround ? ground_ : by_part_[episode.part];
}

const SearchSpace& FootballTrapTask::PartSpace(const Env& env) const {
  const football::TrapEpisode& t = AsFootballEnv(env).state().trap;
  return t.pass.kind == football::PassKind::kGround ? ground_space_ : part_space_[t.part];
}

SearchSpace FootballTrapTask::RescueSpaceAt(const Env& env) const { return PartSpace(env); }

void FootballTrapTask::Restrict(const Env& env, const std::vector<double>&, SearchSpace* space,
                                std::vector<std::vector<double>>*) const {
  *space = PartSpace(env);
}

int FootballTrapTask::max_run_on_steps() const { return kTrapRunOnSteps; }

void FootballTrapTask::Action(const Env& env, const double* theta, PlanClock, const double* prior,
                              float* action) const {
  ActionWithLeg(env, theta, LegChange{}, prior, action);
}

void FootballTrapTask::ActionWithLeg(const Env& env, const double* theta, const LegChange& extra,
                                     const double* prior, float* action) const {
  const FootballEnv& e = AsFootballEnv(env);
  double a[football::kNumActions] = {0};
  if (prior != nullptr) std::copy_n(prior, football::kNumActions, a);
  humanoid::CharacterPose to;
  const config::TrapPlanning& p = PlanningFor(e.state().trap);
  TrapReachPose(*spec_, theta, e.state().trap.pass.meet_s, e.time_s(), ReachRampsOf(p), &to, extra,
                p.squat());
  AddPoseChangeAction(spec_->joints(), spec_->standing_pose(), to,
                      spec_->football().action_torque(), a);
  for (int i = 0; i < football::kNumActions; ++i) {
    action[i] = static_cast<float>(std::clamp(a[i], -1.0, 1.0));
  }
}

std::unique_ptr<RolloutScorer> FootballTrapTask::NewScorer() const {
  return std::make_unique<TrapScorer>(settings_, *this, horizon_);
}

std::vector<std::string> FootballTrapTask::term_names() const {
  return {"reach", "relative_speed", "keep", "miss", "handball", "failure", "upright"};
}

std::vector<std::string> FootballTrapTask::outcome_names() const { return {"relative_mps"}; }

const float* FootballTrapTask::AppliedAction(const Env& env) const {
  return AsFootballEnv(env).state().previous_action.data();
}

std::string FootballTrapTask::DescribeDecision(const std::vector<double>& d,
                                               const std::vector<double>& outcome) const {
  if (d.size() != kTrapVariables) return "";
  std::string out = absl::StrFormat(
      "  reach %+.0f ms hip %+.2f abd %+.2f knee %+.2f ankle %+.2f lean %+.2f chest %+.2f neck %+.2f "
      "give %.2f",
      d[0] * 1000, d[1], d[2], d[3], d[4], d[5], d[6], d[7], d[8]);
  if (outcome.size() == 1) absl::StrAppendFormat(&out, "  trap: relative %.2f m/s", outcome[0]);
  return out;
}

}  // namespace juggle::planner

#include "planner/football/trap_kick_task.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "envs/football/env.h"
#include "envs/football/outcomes.h"
#include "envs/football/trap_kick.h"
#include "planner/football/free_ball.h"
#include "planner/soccer_juggle/plan.h"

namespace juggle::planner {
namespace {

using football::AsFootballEnv;
using football::FootballEnv;

// The zone term: reach × 4 × (√(1 + (distance / kZoneScale)²) − 1), quadratic near the zone and
// linear far from it, so a ball the trap sends metres away costs less than a miss (a squared
// distance of 5 m would outweigh it and the search would rather miss the ball).
constexpr double kZoneScale = 0.5;
// How finely the free path is followed (s), and for at most how long.
constexpr double kZonePathStep = 0.01, kZonePathSeconds = 3.0;

// The second touch's search space (kSecondTouchVariables; empty when off).
SearchSpace SecondTouchSpace(const config::SecondTouch& c) {
  if (!c.enabled()) return SearchSpace{};
  return ReachSpace(c.earliest_s(), c.latest_s(), c.timing_sigma_s(), kSecondTouchVariables - 2,
                    c.angle_limit(), c.angle_sigma());
}

SearchSpace Concat(const SearchSpace& a, const SearchSpace& b) {
  SearchSpace out = a;
  out.lower.insert(out.lower.end(), b.lower.begin(), b.lower.end());
  out.upper.insert(out.upper.end(), b.upper.begin(), b.upper.end());
  out.sigma.insert(out.sigma.end(), b.sigma.begin(), b.sigma.end());
  return out;
}

// The trap's scorer until the env switches to the kick (finished at the switch's state), the
// kick's from there; the zone and out_of_reach terms of its own.
class TrapKickScorer final : public RolloutScorer {
 public:
  TrapKickScorer(const FootballTrapTask& trap_task, std::unique_ptr<RolloutScorer> trap,
                 const FootballKickTask& kick)
      : trap_task_(trap_task), trap_(std::move(trap)), kick_task_(kick) {}

  void Begin(const Env& env) override {
    if (AsFootballEnv(env).kicking()) {
      BeginKick(env);  // the trap is over: it has nothing to score
    } else {
      trap_->Begin(env);
      trap_running_ = true;
    }
  }

  void AfterStep(const Env& env, const float* action, const StepResult& r) override {
    ++steps_;
    if (kick_ != nullptr) {
      kick_->AfterStep(env, action, r);
      return;
    }
    trap_->AfterStep(env, action, r);
    if (r.outcome == football::kOutOfReach) out_of_reach_ = Planning(env).miss();
    if (AsFootballEnv(env).kicking()) {
      trap_->Finish(env);  // the trap's terms at the switch
      trap_running_ = false;
      BeginKick(env);
    }
  }

  double Finish(const Env& env) override {
    const FootballEnv& e = AsFootballEnv(env);
    if (trap_running_) {
      trap_->Finish(env);
      trap_running_ = false;
    }
    if (kick_ != nullptr) kick_->Finish(env);
    const football::TrapEpisode& t = e.state().trap;
    if (!e.kicking() && out_of_reach_ == 0 && t.first_body >= 0 &&
        t.first_body == e.spec().trap_bodies().body[t.part]) {
      const double d = FreePathZoneDistance(env) / kZoneScale;
      zone_ = Planning(env).reach() * 4 * (std::sqrt(1 + d * d) - 1);
    }
    return partial();
  }

  double partial() const override {
    return trap_->partial() + zone_ + out_of_reach_ + (kick_ != nullptr ? kick_->partial() : 0);
  }

  bool RunsOn(const Env& env) const override {
    return kick_ != nullptr ? kick_->RunsOn(env) : trap_->RunsOn(env);
  }

  std::vector<double> terms() const override {
    std::vector<double> out = trap_->terms();
    out.push_back(zone_);
    out.push_back(out_of_reach_);
    if (kick_ != nullptr) {
      const std::vector<double> kick = kick_->terms();
      out.insert(out.end(), kick.begin(), kick.end());
    } else {
      out.resize(out.size() + kick_task_.term_names().size(), 0.0);
    }
    return out;
  }

 private:
  void BeginKick(const Env& env) {
    kick_ = kick_task_.NewScorerFrom(steps_);
    kick_->Begin(env);
  }

  // The trap's settings for `env`'s pass (its part's, TrapPlanningFor).
  const config::TrapPlanning& Planning(const Env& env) const {
    return trap_task_.PlanningFor(AsFootballEnv(env).state().trap);
  }

  const FootballTrapTask& trap_task_;
  std::unique_ptr<RolloutScorer> trap_;
  const FootballKickTask& kick_task_;
  std::unique_ptr<RolloutScorer> kick_;  // from the switch on
  bool trap_running_ = false;
  int steps_ = 0;
  double zone_ = 0, out_of_reach_ = 0;
};

}  // namespace

double FreePathZoneDistance(const Env& env) {
  const FootballEnv& e = AsFootballEnv(env);
  const football::FootballSpec& spec = e.spec();
  const config::TrapThenKick& z = spec.football().trap_kick();
  const football::TrapEpisode& t = e.state().trap;
  const double deadline =
      t.first_touch_s >= 0 ? t.first_touch_s + z.wait_s() : e.data()->time + kZonePathSeconds;
  FreeBall ball(e, /*bounces=*/true);  // a ball still hopping is not yet in the zone
  double best = std::numeric_limits<double>::infinity();
  for (double now = e.data()->time;; now += kZonePathStep) {
    if (ball.on_turf()) {
      const double speed = std::sqrt(ball.v[0] * ball.v[0] + ball.v[1] * ball.v[1]);
      best = std::min(best, football::KickZoneDistance(spec, ball.p[0], ball.p[1]) +
                                0.5 * std::max(0.0, speed - z.max_speed_mps()));
    }
    if (now >= deadline - 1e-9 || now - e.data()->time >= kZonePathSeconds) break;
    ball.Step(kZonePathStep);
  }
  if (!std::isfinite(best)) {  // still in the air at the deadline: where it is
    best = football::KickZoneDistance(spec, ball.p[0], ball.p[1]) + ball.p[2];
  }
  return best;
}

FootballTrapKickTask::FootballTrapKickTask(std::shared_ptr<const football::FootballSpec> spec,
                                           const config::PlannerConfig& config)
    : spec_(spec),
      horizon_(config.horizon_steps()),
      trap_(spec, config),
      kick_(spec, config),
      second_(config.football().second_touch().enabled() ? kSecondTouchVariables : 0),
      space_(Concat(Concat(trap_.space(), SecondTouchSpace(config.football().second_touch())),
                    kick_.space())),
      rescue_space_(
          Concat(Concat(trap_.rescue_space(), SecondTouchSpace(config.football().second_touch())),
                 kick_.rescue_space())) {}

LegChange FootballTrapKickTask::SecondTouchChange(const Env& env, const double* theta) const {
  LegChange out;
  if (second_ == 0) return out;
  const double* v = theta + kTrapVariables;
  const football::TrapEpisode& t = AsFootballEnv(env).state().trap;
  if (t.first_touch_s < 0) return out;  // its own decision, after the touch
  const double w = ReachWeight(t.first_touch_s + v[0], v[5], AsFootballEnv(env).time_s(),
                               ReachRampsOf(trap_.PlanningFor(t)));
  if (w <= 0) return out;
  out.hip = w * v[1];
  out.abduction = w * v[2];
  out.knee = w * v[3];
  out.ankle = w * v[4];
  return out;
}

SearchSpace FootballTrapKickTask::WithPartSpace(const Env& env, SearchSpace space) const {
  const SearchSpace& part = trap_.PartSpace(env);
  std::copy(part.lower.begin(), part.lower.end(), space.lower.begin());
  std::copy(part.upper.begin(), part.upper.end(), space.upper.begin());
  std::copy(part.sigma.begin(), part.sigma.end(), space.sigma.begin());
  return space;
}

SearchSpace FootballTrapKickTask::RescueSpaceAt(const Env& env) const {
  return WithPartSpace(env, rescue_space_);
}

int FootballTrapKickTask::KnotAtOrBefore(int step) const { return kick_.KnotAtOrBefore(step); }

int FootballTrapKickTask::max_run_on_steps() const {
  return std::max(trap_.max_run_on_steps(), kick_.max_run_on_steps());
}

std::vector<double> FootballTrapKickTask::Shift(const std::vector<double>& theta, int grid_steps,
                                                int cycles) const {
  std::vector<double> trap(theta.begin(), theta.begin() + kTrapVariables);
  std::vector<double> kick(theta.begin() + kick_offset(), theta.end());
  std::vector<double> out = trap_.Shift(trap, grid_steps, cycles);
  // The second touch is on the episode's clock, as the trap.
  out.insert(out.end(), theta.begin() + kTrapVariables, theta.begin() + kick_offset());
  const std::vector<double> shifted_kick = kick_.Shift(kick, grid_steps, cycles);
  out.insert(out.end(), shifted_kick.begin(), shifted_kick.end());
  return out;
}

void FootballTrapKickTask::Restrict(const Env& env, const std::vector<double>& shifted,
                                    SearchSpace* space,
                                    std::vector<std::vector<double>>* seeds) const {
  const FootballEnv& e = AsFootballEnv(env);
  *space = WithPartSpace(env, std::move(*space));
  // After the switch the trap is over: its reach and the second touch are held. With a second
  // touch the search before the designated part's touch is the trap's alone (the second touch
  // held at no change), and after it the second touch's (the trap's reach held).
  int first = 0, end = 0;
  if (e.kicking()) {
    end = kick_offset();
  } else if (second_ > 0 && e.state().trap.first_touch_s < 0) {
    first = kTrapVariables;
    end = kick_offset();
  } else if (second_ > 0) {
    end = kTrapVariables;
  }
  for (int v = first; v < end; ++v) {
    space->lower[v] = space->upper[v] = shifted[v];
    space->sigma[v] = 0;
  }
  for (std::vector<double>& seed : *seeds) {
    std::copy(shifted.begin() + first, shifted.begin() + end, seed.begin() + first);
  }
}

void FootballTrapKickTask::Action(const Env& env, const double* theta, PlanClock clock,
                                  const double* prior, float* action) const {
  if (AsFootballEnv(env).kicking()) {
    kick_.Action(env, theta + kick_offset(), clock, prior, action);
  } else {
    trap_.ActionWithLeg(env, theta, SecondTouchChange(env, theta), prior, action);
  }
}

std::unique_ptr<RolloutScorer> FootballTrapKickTask::NewScorer() const {
  return std::make_unique<TrapKickScorer>(trap_, trap_.NewScorer(), kick_);
}

std::vector<std::string> FootballTrapKickTask::term_names() const {
  std::vector<std::string> names = trap_.term_names();
  names.push_back("zone");
  names.push_back("out_of_reach");
  for (const std::string& name : kick_.term_names()) names.push_back("kick_" + name);
  return names;
}

const float* FootballTrapKickTask::AppliedAction(const Env& env) const {
  return AsFootballEnv(env).state().previous_action.data();
}

std::string FootballTrapKickTask::DescribeDecision(const std::vector<double>& d,
                                                   const std::vector<double>& outcome) const {
  if (static_cast<int>(d.size()) != dim()) return "";
  const std::vector<double> trap(d.begin(), d.begin() + kTrapVariables);
  const std::vector<double> kick(d.begin() + kick_offset(), d.end());
  std::string second;
  if (second_ > 0) {
    const double* v = d.data() + kTrapVariables;
    second = absl::StrFormat(
        " | second %+.0f ms hip %+.2f abd %+.2f knee %+.2f ankle %+.2f give %.2f", v[0] * 1000,
        v[1], v[2], v[3], v[4], v[5]);
  }
  return absl::StrCat(trap_.DescribeDecision(trap, {}), second, " |",
                      kick_.DescribeDecision(kick, {}));
}

}  // namespace juggle::planner

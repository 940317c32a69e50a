// The soccer planner on the real simulator: its plans execute exactly as predicted, it rescues
// a kick the base controller misses, it is deterministic for a seed, and its actions replayed
// through a plain env give the same episode; the impact acceleration it can score is measured
// right, costs what its band says, and is reported for every kick an evaluation executes.
#include "planner/receding_horizon.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <vector>

#include "absl/strings/numbers.h"
#include "absl/strings/str_cat.h"
#include "absl/strings/str_split.h"
#include "common/file_io.h"
#include "common/testing/constant_policy.h"
#include "common/testing/temp_dir.h"
#include "envs/registry.h"
#include "envs/testing/test_configs.h"
#include "gtest/gtest.h"
#include "eval/episode_runner.h"
#include "planner/impact_observer.h"
#include "planner/policy_prior.h"
#include "planner/rescue_sample_log.h"
#include "planner/soccer_juggle/cost.h"
#include "planner/soccer_juggle/plan.h"
#include "planner/soccer_juggle/task.h"
#include "planner/soccer_juggle/test_kicks.h"

namespace juggle::planner {
namespace {

using soccer_juggle::JuggleEnv;
using soccer_juggle::JuggleSpec;
using soccer_juggle::kNumActions;

// The receding-horizon driver with the soccer juggling task, with the soccer-typed accessors
// these tests read (the kick outcome, the plan layout).
class SoccerPlanner : public RecedingHorizonPlanner {
 public:
  SoccerPlanner(std::shared_ptr<const JuggleSpec> spec, const config::PlannerConfig& config,
                RolloutPool* pool, uint64_t stream, const ActionPrior* prior = nullptr)
      : RecedingHorizonPlanner(std::make_shared<SoccerJuggleTask>(std::move(spec), config), config,
                               pool, stream, prior) {}
  const SoccerPlanLayout& layout() const {
    return static_cast<const SoccerJuggleTask&>(task()).layout();
  }
  absl::StatusOr<double> Evaluate(const JuggleEnv& env, const std::vector<double>& theta,
                                  KickOutcome* kick = nullptr, int draw = 0) {
    std::vector<double> outcome;
    absl::StatusOr<double> cost = RecedingHorizonPlanner::Evaluate(env, theta, &outcome, draw);
    if (kick != nullptr) *kick = KickOutcomeOf(outcome);
    return cost;
  }
};

// The predicted kick of a re-plan.
KickOutcome PredictedKick(const ReplanReport& r) { return KickOutcomeOf(r.predicted_outcome); }

class SoccerPlannerTest : public ::testing::Test {
 protected:
  void SetUp() override {
    absl::StatusOr<LoadedConfig> config = SmallRightFootPlanner();
    ASSERT_TRUE(config.ok()) << config.status();
    config_ = *config;
    absl::StatusOr<std::shared_ptr<const EnvSpec>> spec = CreateEnvSpec(config_);
    ASSERT_TRUE(spec.ok()) << spec.status();
    spec_ = std::dynamic_pointer_cast<const JuggleSpec>(*spec);
    walk_ = std::make_unique<AdaptiveWalk>(&spec_->graph());
    pool_ = std::make_unique<RolloutPool>(spec_, 2);
    down_ = *spec_->graph().FindNode("right_foot_down");
  }

  // An env at the apex of a DOWN node with the ball `forward` m ahead of its target.
  std::unique_ptr<JuggleEnv> StartWithBallAhead(double forward, uint64_t seed = 3) {
    auto env = std::make_unique<JuggleEnv>(spec_, Rng(seed));
    env->ResetAt(down_, *walk_);
    mjData* d = env->data();
    d->qpos[spec_->ball_qpos()] += forward;
    mj_forward(spec_->model(), d);
    return env;
  }

  std::unique_ptr<SoccerPlanner> NewPlanner(uint64_t seed = 1) {
    config::PlannerConfig p = config_.run.planner();
    p.set_seed(seed);
    return std::make_unique<SoccerPlanner>(spec_, p, pool_.get(), 0);
  }

  // One re-plan of a new planner (kept in *planner) on a start with the ball `ahead` m ahead.
  ReplanReport PlanOnce(double ahead, std::unique_ptr<SoccerPlanner>* planner) {
    std::unique_ptr<JuggleEnv> env = StartWithBallAhead(ahead);
    *planner = NewPlanner();
    float action[kNumActions];
    EXPECT_TRUE((*planner)->Act(*env, action).ok());
    return (*planner)->last_replan();
  }

  LoadedConfig config_;
  std::shared_ptr<const JuggleSpec> spec_;
  std::unique_ptr<AdaptiveWalk> walk_;
  std::unique_ptr<RolloutPool> pool_;
  int down_ = -1;
};

// The rescue of a kick the base controller misses, executed exactly as predicted: the foot's
// with the knee's and the header's in SkillRescueTest (skills_rescue_test.cc).

// The planner's actions over `steps` steps of `env`, which it drives.
std::vector<float> ActionsOver(SoccerPlanner* planner, JuggleEnv* env, const AdaptiveWalk& walk,
                               int steps) {
  std::vector<float> actions;
  float action[kNumActions];
  for (int t = 0; t < steps; ++t) {
    EXPECT_TRUE(planner->Act(*env, action).ok());
    actions.insert(actions.end(), action, action + kNumActions);
    env->Step(action, walk);
  }
  return actions;
}

TEST_F(SoccerPlannerTest, TheSameSeedGivesTheSamePlan) {
  std::vector<std::vector<float>> runs;
  for (uint64_t seed : {7, 7, 8}) {
    std::unique_ptr<JuggleEnv> env = StartWithBallAhead(0.03);
    runs.push_back(ActionsOver(NewPlanner(seed).get(), env.get(), *walk_, 12));
  }
  EXPECT_EQ(runs[0], runs[1]);
  EXPECT_NE(runs[0], runs[2]);
}

// prune_chunk: the same search in groups whose bound tightens between them chooses the same
// plans, the rescue's included, from fewer rollout steps.
TEST_F(SoccerPlannerTest, PruningInGroupsChoosesTheSamePlansFromFewerRolloutSteps) {
  config::PlannerConfig& p = *config_.run.mutable_planner();
  ASSERT_TRUE(p.prune());
  p.mutable_rescue()->set_cost_above(1e-9);  // every re-plan rescued
  p.mutable_rescue()->set_samples(24);
  p.mutable_rescue()->set_iterations(3);
  std::vector<float> actions[2];
  PlannerTotals totals[2];
  for (int arm = 0; arm < 2; ++arm) {
    p.set_prune_chunk(arm == 0 ? 0 : 4);
    std::unique_ptr<JuggleEnv> env = StartWithBallAhead(0.12);
    std::unique_ptr<SoccerPlanner> planner = NewPlanner();
    actions[arm] = ActionsOver(planner.get(), env.get(), *walk_, 12);
    totals[arm] = planner->totals();
  }
  EXPECT_EQ(actions[1], actions[0]);
  EXPECT_EQ(totals[1].rescues, totals[0].rescues);
  EXPECT_EQ(totals[0].rescues, 3);
  EXPECT_EQ(totals[1].rollouts, totals[0].rollouts);
  EXPECT_LT(totals[1].rollout_steps, totals[0].rollout_steps * 0.95)
      << totals[1].rollout_steps << " against " << totals[0].rollout_steps;
}

TEST_F(SoccerPlannerTest, ItsActionsReplayedInAPlainEnvGiveTheSameEpisode) {
  std::unique_ptr<JuggleEnv> env = StartWithBallAhead(0.03);
  std::unique_ptr<SoccerPlanner> planner = NewPlanner();
  std::vector<std::vector<float>> actions;
  float action[kNumActions];
  for (int t = 0; t < 50; ++t) {
    ASSERT_TRUE(planner->Act(*env, action).ok());
    actions.emplace_back(action, action + kNumActions);
    if (env->Step(action, *walk_).outcome != Outcome::kRunning) break;
  }
  ASSERT_GE(env->juggles(), 1) << "the planned stretch should hold a kick";
  // The labels alone, without the planner: the same start, the same actions.
  std::unique_ptr<JuggleEnv> replay = StartWithBallAhead(0.03);
  for (const std::vector<float>& a : actions) replay->Step(a.data(), *walk_);
  EXPECT_EQ(replay->juggles(), env->juggles());
  EXPECT_EQ(replay->steps(), env->steps());
  PhysicsSnapshot a, b;
  a.Save(spec_->model(), env->data());
  EXPECT_TRUE(a.Equals(replay->data()));
}

TEST_F(SoccerPlannerTest, WithAPolicyPriorItsActionsReplayedInAPlainEnvGiveThePlannedEpisode) {
  // The proposal: a policy whose mean action is 0.02 on every joint, the plan's offsets on top.
  PolicyPrior prior(*spec_);
  ASSERT_TRUE(prior.Set(std::make_shared<const EigenPolicy>(::juggle::testing::ConstantPolicy(
                            spec_->obs_dim(), spec_->act_dim(), std::atanh(0.02f))))
                  .ok());
  std::unique_ptr<JuggleEnv> env = StartWithBallAhead(0.03);
  SoccerPlanner planner(spec_, config_.run.planner(), pool_.get(), 0, &prior);
  std::vector<std::vector<float>> actions;
  float action[kNumActions];
  for (int t = 0; t < 50; ++t) {
    ASSERT_TRUE(planner.Act(*env, action).ok());
    actions.emplace_back(action, action + kNumActions);
    if (env->Step(action, *walk_).outcome != Outcome::kRunning) break;
  }
  EXPECT_GT(planner.totals().prediction_checks, 40);
  EXPECT_EQ(planner.totals().prediction_mismatches, 0);
  // The actions carry the prior: the first one differs from the same planner's without it.
  std::unique_ptr<JuggleEnv> plain_start = StartWithBallAhead(0.03);
  SoccerPlanner plain(spec_, config_.run.planner(), pool_.get(), 0);
  float first[kNumActions];
  ASSERT_TRUE(plain.Act(*plain_start, first).ok());
  EXPECT_NE(std::vector<float>(first, first + kNumActions), actions.front());
  // The labels alone, without the planner or the policy: the same start, the same episode.
  std::unique_ptr<JuggleEnv> replay = StartWithBallAhead(0.03);
  for (const std::vector<float>& a : actions) replay->Step(a.data(), *walk_);
  EXPECT_EQ(replay->juggles(), env->juggles());
  EXPECT_EQ(replay->steps(), env->steps());
  PhysicsSnapshot a;
  a.Save(spec_->model(), env->data());
  EXPECT_TRUE(a.Equals(replay->data()));
}

TEST_F(SoccerPlannerTest, AReleasedKickKeepsItsVariablesUntilTheNextCycle) {
  config_.run.mutable_planner()->mutable_soccer_juggle()->mutable_kick()->set_freeze_after_release(true);
  std::unique_ptr<JuggleEnv> env = StartWithBallAhead(0.03);
  std::unique_ptr<SoccerPlanner> planner = NewPlanner();
  float action[kNumActions];
  std::vector<double> at_release;
  int replans_after = 0;
  for (int t = 0; t < 60; ++t) {
    const bool released = env->state().kick_touched && !env->state().touched_this_step;
    ASSERT_TRUE(planner->Act(*env, action).ok());
    const std::vector<double> kick(planner->plan().begin(), planner->plan().begin() + kKickVariables);
    if (released && planner->last_replan().env_step == env->steps()) {
      if (at_release.empty()) {
        at_release = kick;
      } else {
        EXPECT_EQ(kick, at_release) << "step " << t;
        ++replans_after;
      }
    }
    if (!at_release.empty() && !env->state().kick_touched) break;  // the next cycle began
    ASSERT_EQ(env->Step(action, *walk_).outcome, Outcome::kRunning);
  }
  EXPECT_GE(replans_after, 3);
}

// A planner that can only choose the nominal swing (zero spreads, no rescue): its plan is the
// zero action, so its predictions can be checked against a plain zero-action rollout.
config::PlannerConfig NominalOnly(config::PlannerConfig p, int horizon) {
  p.mutable_soccer_juggle()->mutable_kick()->set_phase_sigma_s(0);
  p.mutable_soccer_juggle()->mutable_kick()->set_angle_sigma(0);
  p.mutable_rescue()->set_cost_above(0);
  p.set_horizon_steps(horizon);
  return p;
}

// A horizon that ends while the foot is on the ball runs on to the release, so the kick is
// scored; its prediction equals what the zero action then does, bit for bit.
TEST_F(SoccerPlannerTest, AHorizonEndingInContactRunsOnToTheReleaseAndScoresTheKick) {
  std::unique_ptr<JuggleEnv> probe = StartWithBallAhead(0.0);
  const float zero[kNumActions] = {0};
  int first_touch = 0;
  for (int t = 1; t <= 60 && first_touch == 0; ++t) {
    ASSERT_EQ(probe->Step(zero, *walk_).outcome, Outcome::kRunning);
    if (probe->state().touched_this_step) first_touch = t;
  }
  ASSERT_GT(first_touch, 1);
  const KickOutcome executed = ZeroActionKick(probe.get(), *walk_);
  ASSERT_TRUE(executed.valid);
  // The current cycle's kick runs on whether or not later cycles' kicks do.
  for (int horizon : {first_touch, first_touch - 1, -first_touch}) {
    config::PlannerConfig p = NominalOnly(config_.run.planner(), std::abs(horizon));
    p.set_run_on_every_kick(horizon > 0);
    horizon = std::abs(horizon);
    std::unique_ptr<JuggleEnv> env = StartWithBallAhead(0.0);
    SoccerPlanner planner(spec_, p, pool_.get(), 0);
    float action[kNumActions];
    ASSERT_TRUE(planner.Act(*env, action).ok());
    for (float a : action) ASSERT_EQ(a, 0.0f);
    const KickOutcome predicted = PredictedKick(planner.last_replan());
    if (horizon == first_touch) {  // ends on the ball: scored at its release
      ASSERT_TRUE(predicted.valid);
      EXPECT_EQ(predicted.timing, executed.timing);
      EXPECT_EQ(predicted.dx, executed.dx);
      EXPECT_EQ(predicted.dy, executed.dy);
    } else {  // ends before the touch: no kick yet
      EXPECT_FALSE(predicted.valid);
    }
  }
}

// run_on_every_kick: false runs on only the current cycle's kick. A horizon that ends with the
// foot on the ball at the next cycle's touch stops there; with true it runs on past it.
TEST_F(SoccerPlannerTest, WithoutRunOnEveryKickALaterCyclesKickIsNotRunOn) {
  // The zero action's second touch, a new touch after the first kick has left the foot (from
  // this start the zero action makes one; from most it does not).
  std::unique_ptr<JuggleEnv> probe = StartWithBallAhead(0.01, 3);
  const float zero[kNumActions] = {0};
  int second_touch = 0;
  bool released = false;
  for (int t = 1; t <= 150 && second_touch == 0; ++t) {
    ASSERT_EQ(probe->Step(zero, *walk_).outcome, Outcome::kRunning) << "step " << t;
    if (probe->state().kick_touched && !probe->state().touched_this_step) released = true;
    if (released && probe->state().touched_this_step) second_touch = t;
  }
  ASSERT_GT(second_touch, 0) << "the zero action should touch the ball a second time";
  for (const bool every : {false, true}) {
    config::PlannerConfig p = NominalOnly(config_.run.planner(), second_touch);
    p.set_run_on_every_kick(every);
    p.set_prune(false);
    std::unique_ptr<JuggleEnv> env = StartWithBallAhead(0.01, 3);
    SoccerPlanner planner(spec_, p, pool_.get(), 0);
    float action[kNumActions];
    ASSERT_TRUE(planner.Act(*env, action).ok());
    const int predicted_steps = planner.last_replan().predicted_end_step - env->steps();
    if (every) {
      EXPECT_GT(predicted_steps, second_touch);
    } else {
      EXPECT_EQ(predicted_steps, second_touch);
    }
  }
}

// Steps `probe` with zero action until its ball leaves the foot a second time (at most 150
// steps); returns each release's kick outcome and sets *second_release to its step (0: none).
std::vector<KickOutcome> ZeroActionReleases(JuggleEnv* probe, const AdaptiveWalk& walk,
                                            int* second_release) {
  const float zero[kNumActions] = {0};
  std::vector<KickOutcome> kicks;
  *second_release = 0;
  bool released = false;  // this cycle's ball has left the foot
  for (int t = 1; t <= 150 && *second_release == 0; ++t) {
    if (probe->Step(zero, walk).outcome != Outcome::kRunning) break;
    const soccer_juggle::JuggleEnvState& s = probe->state();
    if (!s.kick_touched) released = false;
    if (!s.kick_touched || s.touched_this_step || released) continue;
    released = true;
    kicks.push_back(PredictKickOutcome(*probe));
    if (kicks.size() == 2) *second_release = t;
  }
  return kicks;
}

// cost.later_kicks weights the kick term of every kick after a rollout's first. Checked
// against both kicks' outcomes taken from a plain zero-action run at their releases and the
// cost's formula (the planner's nominal plan is the zero action).
TEST_F(SoccerPlannerTest, LaterKicksWeightsTheKickTermOfEveryKickAfterTheRolloutsFirst) {
  std::unique_ptr<JuggleEnv> probe = StartWithBallAhead(0.01, 3);
  int second_release = 0;
  const std::vector<KickOutcome> kicks = ZeroActionReleases(probe.get(), *walk_, &second_release);
  ASSERT_EQ(kicks.size(), 2u) << "the zero action should release the ball twice";
  const config::PlannerCost& w = config_.run.planner().soccer_juggle().cost();
  auto kick_cost = [&](const KickOutcome& k) {
    return w.kick() * (std::pow(k.timing / w.timing_scale_s(), 2) +
                       (k.dx * k.dx + k.dy * k.dy) / std::pow(w.landing_scale(), 2) +
                       w.apex_weight() * std::pow(k.apex / w.apex_scale(), 2));
  };
  const double first = kick_cost(kicks[0]), second = kick_cost(kicks[1]);
  ASSERT_GT(second, 0);
  for (const double later : {1.0, 0.25, 0.0}) {
    config::PlannerConfig p = NominalOnly(config_.run.planner(), second_release + 2);
    p.set_prune(false);
    p.mutable_soccer_juggle()->mutable_cost()->set_later_kicks(later);
    std::unique_ptr<JuggleEnv> env = StartWithBallAhead(0.01, 3);
    SoccerPlanner planner(spec_, p, pool_.get(), 0);
    float action[kNumActions];
    ASSERT_TRUE(planner.Act(*env, action).ok());
    const std::vector<double>& terms = planner.last_replan().terms;
    ASSERT_EQ(terms.size(), SoccerTermNames().size());
    EXPECT_NEAR(terms[2], first + later * second, 1e-9 * (first + second)) << "later_kicks " << later;
  }
}

// rescue.ignore_later_kicks: a plan in trouble only by its later kick's cost gets no rescue; the
// same plan in trouble by its own cost does. The threshold sits between the plan's cost with
// and without the later kick (measured with later_kicks at 1 and at 0).
TEST_F(SoccerPlannerTest, ARescueTriggerWithoutLaterKicksSkipsTroubleOnlyTheLaterKickMakes) {
  std::unique_ptr<JuggleEnv> probe = StartWithBallAhead(0.01, 3);
  int second_release = 0;
  ZeroActionReleases(probe.get(), *walk_, &second_release);
  ASSERT_GT(second_release, 0) << "the zero action should release the ball twice";
  const config::PlannerConfig nominal = NominalOnly(config_.run.planner(), second_release + 2);
  auto replan = [&](const config::PlannerConfig& p) {
    std::unique_ptr<JuggleEnv> env = StartWithBallAhead(0.01, 3);
    SoccerPlanner planner(spec_, p, pool_.get(), 0);
    float action[kNumActions];
    EXPECT_TRUE(planner.Act(*env, action).ok());
    return planner.last_replan();
  };
  config::PlannerConfig p = nominal;
  p.set_prune(false);
  const double with_later = replan(p).best_cost;
  p.mutable_soccer_juggle()->mutable_cost()->set_later_kicks(0);
  const double without_later = replan(p).best_cost;
  ASSERT_LT(without_later, with_later);
  for (const bool ignore : {false, true}) {
    for (const double above : {0.5 * (with_later + without_later), 0.5 * without_later}) {
      config::PlannerConfig q = nominal;
      q.set_prune(false);
      q.mutable_rescue()->set_cost_above(above);
      q.mutable_rescue()->set_ignore_later_kicks(ignore);
      q.mutable_rescue()->set_samples(8);
      q.mutable_rescue()->set_iterations(1);
      const bool own_trouble = above < without_later;
      EXPECT_EQ(replan(q).rescued, own_trouble || !ignore)
          << "ignore_later_kicks " << ignore << ", cost_above " << above;
    }
  }
}

// With replan_at_cycle_start the planner decides once per juggle cycle: it re-plans at the
// episode's first step and at every DOWN entry, nowhere else, and acts open loop in between.
TEST_F(SoccerPlannerTest, ReplanAtCycleStartReplansOnlyWhenADownNodeIsEntered) {
  config::PlannerConfig p = config_.run.planner();
  p.set_replan_at_cycle_start(true);
  SoccerPlanner planner(spec_, p, pool_.get(), 0);
  std::unique_ptr<JuggleEnv> env = StartWithBallAhead(0.0);
  std::vector<int> down_entries = {env->steps()};
  std::vector<int> replan_steps;
  int64_t replans = 0;
  int node = env->node();
  float action[kNumActions];
  for (int t = 0; t < 120; ++t) {
    if (env->node() != node) {
      node = env->node();
      if (spec_->graph().node(node).stage == config::DOWN) down_entries.push_back(env->steps());
    }
    ASSERT_TRUE(planner.Act(*env, action).ok());
    if (planner.totals().replans != replans) {
      replans = planner.totals().replans;
      replan_steps.push_back(planner.last_replan().env_step);
    }
    if (env->Step(action, *walk_).outcome != Outcome::kRunning) break;
  }
  ASSERT_GE(down_entries.size(), 2u) << "the planner's kick should bring the ball back down";
  EXPECT_EQ(replan_steps, down_entries);
  EXPECT_EQ(planner.totals().prediction_mismatches, 0);
}

// A horizon that ends after the clock has passed the contact with no touch in the cycle
// predicts a miss, which costs a failure; one that ends before the contact does not.
TEST_F(SoccerPlannerTest, AHorizonEndingPastAMissedContactCostsAFailure) {
  // The ball 1 m higher: it comes down long after the swing has passed.
  auto late_ball = [&] {
    std::unique_ptr<JuggleEnv> env = StartWithBallAhead(0.0);
    env->data()->qpos[spec_->ball_qpos() + 2] += 1.0;
    mj_forward(spec_->model(), env->data());
    return env;
  };
  // The node turns UP without a touch within 40 steps of zero action, and nothing ends.
  std::unique_ptr<JuggleEnv> probe = late_ball();
  const float zero[kNumActions] = {0};
  int up_at = 0;
  for (int t = 1; t <= 40 && up_at == 0; ++t) {
    ASSERT_EQ(probe->Step(zero, *walk_).outcome, Outcome::kRunning);
    ASSERT_FALSE(probe->state().kick_touched);
    if (spec_->graph().node(probe->node()).stage == config::UP) up_at = t;
  }
  ASSERT_GT(up_at, 2);
  const double failure = config_.run.planner().soccer_juggle().cost().failure();
  for (int horizon : {up_at + 2, up_at - 2}) {
    std::unique_ptr<JuggleEnv> env = late_ball();
    SoccerPlanner planner(spec_, NominalOnly(config_.run.planner(), horizon), pool_.get(), 0);
    float action[kNumActions];
    ASSERT_TRUE(planner.Act(*env, action).ok());
    const ReplanReport& r = planner.last_replan();
    if (horizon > up_at) {
      EXPECT_TRUE(r.predicts_miss);
      EXPECT_GE(r.best_cost, failure);
    } else {
      EXPECT_FALSE(r.predicts_miss);
      EXPECT_LT(r.best_cost, failure);
    }
  }
}

// The rescue search (PlannerConfig.rescue) runs only for a re-plan whose best plan costs more
// than its threshold, starts from that plan, and so never returns a costlier one.
TEST_F(SoccerPlannerTest, AfterARescueThatStillLosesTheBallTheNextReplansRunNone) {
  // The ball 0.6 m ahead of its target at the apex: no kick reaches it, and every rescue's best
  // plan still predicts the lost ball.
  config::RescueSearch& rescue = *config_.run.mutable_planner()->mutable_rescue();
  rescue.set_cost_above(500);
  rescue.set_samples(8);
  rescue.set_iterations(2);
  struct Replan {
    bool rescued;
    bool predicts_failure;
  };
  std::vector<Replan> arms[2];
  PlannerTotals totals[2];
  for (int arm = 0; arm < 2; ++arm) {
    rescue.set_pause_after_lost(arm == 0 ? 0 : 3);
    std::unique_ptr<JuggleEnv> env = StartWithBallAhead(0.6);
    std::unique_ptr<SoccerPlanner> planner = NewPlanner();
    float action[kNumActions];
    for (int t = 0; t < 200; ++t) {
      const int64_t replans = planner->totals().replans;
      ASSERT_TRUE(planner->Act(*env, action).ok());
      if (planner->totals().replans > replans) {
        arms[arm].push_back(
            {planner->last_replan().rescued, planner->last_replan().predicts_failure});
      }
      if (env->Step(action, *walk_).outcome != Outcome::kRunning) break;
    }
    totals[arm] = planner->totals();
  }
  // Without a pause every re-plan rescues, and each rescue still predicts the loss.
  ASSERT_GE(arms[0].size(), 6u);
  for (const Replan& r : arms[0]) {
    EXPECT_TRUE(r.rescued);
    EXPECT_TRUE(r.predicts_failure);
  }
  EXPECT_EQ(totals[0].rescues_paused, 0);
  // With a pause of 3: a rescue, then three re-plans without one, then a rescue again (the
  // plans differ, so the episode may end at another step).
  ASSERT_GE(arms[1].size(), 6u);
  int paused = 0;
  for (size_t i = 0; i < arms[1].size(); ++i) {
    EXPECT_EQ(arms[1][i].rescued, i % 4 == 0) << "re-plan " << i;
    paused += !arms[1][i].rescued;
  }
  EXPECT_EQ(totals[1].rescues_paused, paused);
  EXPECT_LT(totals[1].rollout_steps / double(arms[1].size()),
            totals[0].rollout_steps / double(arms[0].size()));
  EXPECT_EQ(totals[1].prediction_mismatches, 0);
}

TEST_F(SoccerPlannerTest, ARescueSearchRunsOnlyAboveItsCostAndNeverRaisesIt) {
  struct Arm {
    double cost_above;
    ReplanReport report;
    PlannerTotals totals;
    std::vector<float> action;
  };
  std::vector<Arm> arms(3);
  arms[0].cost_above = 0;  // off
  arms[1].cost_above = 1e-9;  // always
  arms[2].cost_above = 1e30;  // never
  for (Arm& arm : arms) {
    config::RescueSearch& rescue = *config_.run.mutable_planner()->mutable_rescue();
    rescue.set_cost_above(arm.cost_above);
    rescue.set_samples(24);
    rescue.set_iterations(3);
    std::unique_ptr<JuggleEnv> env = StartWithBallAhead(0.12);
    std::unique_ptr<SoccerPlanner> planner = NewPlanner();
    arm.action.resize(kNumActions);
    ASSERT_TRUE(planner->Act(*env, arm.action.data()).ok());
    arm.report = planner->last_replan();
    arm.totals = planner->totals();
  }
  const Arm &off = arms[0], &always = arms[1], &never = arms[2];
  EXPECT_FALSE(off.report.rescued);
  EXPECT_EQ(off.totals.rescues, 0);
  EXPECT_TRUE(always.report.rescued);
  EXPECT_EQ(always.totals.rescues, 1);
  EXPECT_GT(always.report.evaluations, off.report.evaluations);
  EXPECT_LE(always.report.best_cost, off.report.best_cost);
  EXPECT_EQ(always.report.incumbent_cost, off.report.incumbent_cost);
  EXPECT_FALSE(never.report.rescued);
  EXPECT_EQ(never.action, off.action);
  EXPECT_EQ(never.report.best_cost, off.report.best_cost);
}

// rescue.refine_after: the rescue's best plan polished by Levenberg–Marquardt steps, the same
// steps as refine_iterations after every re-plan (the independent path: here every re-plan is
// rescued), and nothing at all where no rescue runs.
TEST_F(SoccerPlannerTest, ARefinementAfterTheRescueIsTheRefinementOfTheRescuesBest) {
  config::PlannerConfig& p = *config_.run.mutable_planner();
  config::RescueSearch& rescue = *p.mutable_rescue();
  rescue.set_samples(24);
  rescue.set_iterations(3);
  const double ahead = 0.06;
  std::unique_ptr<SoccerPlanner> planner;
  rescue.set_cost_above(1e-9);  // every re-plan rescued
  const ReplanReport rescued = PlanOnce(ahead, &planner);
  ASSERT_TRUE(rescued.rescued);
  p.set_refine_iterations(2);
  const ReplanReport refined_every = PlanOnce(ahead, &planner);
  const std::vector<double> refined_every_plan = planner->plan();
  const int64_t refined_every_rollouts = planner->totals().rollouts;
  p.set_refine_iterations(0);
  rescue.set_refine_after(2);
  const ReplanReport refined_after = PlanOnce(ahead, &planner);
  EXPECT_EQ(planner->plan(), refined_every_plan);
  EXPECT_EQ(refined_after.best_cost, refined_every.best_cost);
  EXPECT_EQ(planner->totals().rollouts, refined_every_rollouts);
  EXPECT_LT(refined_after.best_cost, rescued.best_cost) << "the rescue's best left room to refine";
  // No rescue, no refinement.
  rescue.set_cost_above(1e30);
  rescue.set_refine_after(0);
  const ReplanReport plain = PlanOnce(ahead, &planner);
  const std::vector<double> plain_plan = planner->plan();
  rescue.set_refine_after(2);
  const ReplanReport plain_after = PlanOnce(ahead, &planner);
  EXPECT_FALSE(plain_after.rescued);
  EXPECT_EQ(planner->plan(), plain_plan);
  EXPECT_EQ(plain_after.best_cost, plain.best_cost);
}

// rescue.full_after_decay: a decayed rescue that ends in trouble is followed by a full one (its
// rollouts are the full rescue's count again: the independent path), and one that ends out of
// trouble is not.
TEST_F(SoccerPlannerTest, AFullRescueFollowsADecayedOneOnlyWhenItEndsInTrouble) {
  config::PlannerConfig& p = *config_.run.mutable_planner();
  p.set_prune(false);  // every candidate a whole rollout: the counts below are exact
  config::RescueSearch& rescue = *p.mutable_rescue();
  rescue.set_samples(24);
  rescue.set_iterations(3);
  const double ahead = 0.06;
  std::unique_ptr<SoccerPlanner> planner;
  // Rollouts of the regular search alone, with a full rescue, with a decayed one.
  rescue.set_cost_above(1e30);
  const ReplanReport plain = PlanOnce(ahead, &planner);
  const int64_t plain_rollouts = planner->totals().rollouts;
  rescue.set_cost_above(1e-9);  // every re-plan in trouble, every rescue ends in it
  PlanOnce(ahead, &planner);
  const int64_t full_rescue = planner->totals().rollouts - plain_rollouts;
  rescue.set_population_decay(2);
  const ReplanReport decayed = PlanOnce(ahead, &planner);
  const int64_t decayed_rescue = planner->totals().rollouts - plain_rollouts;
  ASSERT_TRUE(decayed.rescued);
  ASSERT_LT(decayed_rescue, full_rescue);
  rescue.set_full_after_decay(true);
  const ReplanReport escalated = PlanOnce(ahead, &planner);
  EXPECT_TRUE(escalated.rescued);
  EXPECT_EQ(planner->totals().full_after_decay, 1);
  EXPECT_EQ(planner->totals().rollouts - plain_rollouts, decayed_rescue + full_rescue);
  EXPECT_LE(escalated.best_cost, decayed.best_cost);
  // A decayed rescue that ends below the bar: no full one.
  ASSERT_GT(plain.best_cost, decayed.best_cost);
  rescue.set_cost_above(0.5 * (plain.best_cost + decayed.best_cost));
  const ReplanReport out = PlanOnce(ahead, &planner);
  EXPECT_TRUE(out.rescued);
  EXPECT_EQ(planner->totals().full_after_decay, 0);
  EXPECT_EQ(planner->totals().rollouts - plain_rollouts, decayed_rescue);
}

// rescue.bayes: the model-based rescue of a far-off kick spends exactly its rollouts, lowers
// the troubled cost, and ends early once a plan is good enough (stop_below).
TEST_F(SoccerPlannerTest, AModelBasedRescueSpendsItsRolloutsAndStopsOnceOutOfTrouble) {
  config::PlannerConfig& p = *config_.run.mutable_planner();
  p.set_prune(false);  // every candidate a whole rollout: the counts below are exact
  config::RescueSearch& rescue = *p.mutable_rescue();
  const double ahead = 0.06;
  std::unique_ptr<SoccerPlanner> planner;
  rescue.set_cost_above(1e30);
  const ReplanReport plain = PlanOnce(ahead, &planner);
  const int64_t plain_rollouts = planner->totals().rollouts;
  rescue.set_cost_above(1e-9);  // every re-plan in trouble
  rescue.mutable_bayes()->set_evaluations(24);
  rescue.mutable_bayes()->set_initial(8);
  const ReplanReport bayes = PlanOnce(ahead, &planner);
  ASSERT_TRUE(bayes.rescued);
  EXPECT_EQ(planner->totals().rescues, 1);
  // Its first batch's three seeds (the regular search's best, the warm start, the nominal kick)
  // are read from the regular search's rollouts, not simulated again.
  EXPECT_EQ(planner->totals().rollouts - plain_rollouts, 24 - 3);
  EXPECT_LT(bayes.best_cost, plain.best_cost);
  // Stopping at the regular search's best (a seed of the rescue's first batch): the first
  // batch ends it. (A loaded config keeps stop_below at or below cost_above; the driver reads
  // them apart.)
  rescue.set_stop_below(plain.best_cost);
  const ReplanReport stopped = PlanOnce(ahead, &planner);
  ASSERT_TRUE(stopped.rescued);
  EXPECT_LT(planner->totals().rollouts - plain_rollouts, 24);
  EXPECT_LE(stopped.best_cost, plain.best_cost);
}

// kick.held_angles: the held angles stay at 0 through the regular search and a rescue (never
// drawn), the others move; against the same re-plan without the hold, whose knee and ankle
// move, so the check can fail.
TEST_F(SoccerPlannerTest, HeldKickAnglesStayAtZeroThroughTheSearchAndTheRescue) {
  config::PlannerConfig& p = *config_.run.mutable_planner();
  p.mutable_rescue()->set_cost_above(1e-9);  // every re-plan rescued
  p.mutable_rescue()->set_samples(16);
  p.mutable_rescue()->set_iterations(2);
  std::unique_ptr<SoccerPlanner> planner;
  ASSERT_TRUE(PlanOnce(0.12, &planner).rescued);
  EXPECT_NE(planner->plan()[3], 0.0);
  EXPECT_NE(planner->plan()[4], 0.0);
  p.mutable_soccer_juggle()->mutable_kick()->add_held_angles(3);
  p.mutable_soccer_juggle()->mutable_kick()->add_held_angles(4);
  ASSERT_TRUE(PlanOnce(0.12, &planner).rescued);
  EXPECT_EQ(planner->plan()[3], 0.0);
  EXPECT_EQ(planner->plan()[4], 0.0);
  EXPECT_NE(planner->plan()[1], 0.0);
  EXPECT_NE(planner->plan()[2], 0.0);
}

// The values of `key`'s array in one JSON line of planner/rescue_sample_log.h ("[]": none).
std::vector<double> LoggedArray(const std::string& line, const std::string& key) {
  const size_t at = line.find("\"" + key + "\":[");
  EXPECT_NE(at, std::string::npos) << key << " in " << line;
  const size_t begin = line.find('[', at) + 1;
  std::vector<double> values;
  for (absl::string_view v : absl::StrSplit(line.substr(begin, line.find(']', begin) - begin), ',',
                                            absl::SkipEmpty())) {
    double x = 0;
    EXPECT_TRUE(absl::SimpleAtod(v, &x)) << v;
    values.push_back(x);
  }
  return values;
}

// --rescue-samples-out: one rescue's record holds its state, every rollout its search scored
// (as many as the planner counted, and the seeds it read), and its best; re-simulating logged
// candidates from the same state is the independent path to their logged costs and outcomes.
TEST_F(SoccerPlannerTest, TheRescueLogHoldsEveryRescueRolloutAsItsSearchScoredIt) {
  config::PlannerConfig& p = *config_.run.mutable_planner();
  p.set_prune(false);  // every candidate a whole rollout
  config::RescueSearch& rescue = *p.mutable_rescue();
  rescue.set_cost_above(1e30);
  std::unique_ptr<SoccerPlanner> planner;
  const ReplanReport plain = PlanOnce(0.06, &planner);
  const int64_t plain_rollouts = planner->totals().rollouts;
  rescue.set_cost_above(1e-9);  // every re-plan in trouble
  rescue.set_samples(12);
  rescue.set_iterations(2);
  const std::string path = MakeTempDir("rescue_log_") + "/samples.jsonl";
  absl::StatusOr<std::unique_ptr<RescueSampleLog>> log =
      RescueSampleLog::Open(path, spec_->obs_dim());
  ASSERT_TRUE(log.ok()) << log.status();
  std::unique_ptr<JuggleEnv> env = StartWithBallAhead(0.06);
  planner = NewPlanner();
  planner->set_rescue_log(log->get());
  float action[kNumActions];
  ASSERT_TRUE(planner->Act(*env, action).ok());
  ASSERT_TRUE(planner->last_replan().rescued);
  ASSERT_TRUE((*log)->Close().ok());
  // Every candidate the rescue scored: those it simulated, and its first batch's three seeds
  // (the regular search's best, the warm start, the nominal kick), read from the regular
  // search's rollouts.
  const int64_t rescue_rollouts = planner->totals().rollouts - plain_rollouts + 3;
  EXPECT_EQ((*log)->rescues(), 1);
  EXPECT_EQ((*log)->rollouts(), rescue_rollouts);

  absl::StatusOr<std::string> text = ReadFile(path);
  ASSERT_TRUE(text.ok());
  std::vector<std::string> lines = absl::StrSplit(*text, '\n', absl::SkipEmpty());
  ASSERT_EQ(static_cast<int64_t>(lines.size()), rescue_rollouts + 2);
  EXPECT_EQ(LoggedArray(lines.front(), "observation").size(),
            static_cast<size_t>(spec_->obs_dim()));
  EXPECT_NE(lines.front().find("\"troubled_cost\":"), std::string::npos);
  EXPECT_NE(lines.back().find(absl::StrCat("\"rollouts\":", rescue_rollouts)), std::string::npos);
  double lowest = std::numeric_limits<double>::infinity();
  for (size_t i = 1; i + 1 < lines.size(); ++i) {
    const std::vector<double> theta = LoggedArray(lines[i], "theta");
    ASSERT_EQ(static_cast<int>(theta.size()), planner->task().dim());
    double cost = 0;
    const size_t colon = lines[i].rfind(':') + 1;
    ASSERT_TRUE(absl::SimpleAtod(lines[i].substr(colon, lines[i].rfind('}') - colon), &cost))
        << lines[i];
    lowest = std::min(lowest, cost);
    if (i % 5 != 1) continue;  // every fifth re-simulated
    std::vector<double> outcome;
    absl::StatusOr<double> again =
        static_cast<RecedingHorizonPlanner&>(*planner).Evaluate(*env, theta, &outcome);
    ASSERT_TRUE(again.ok());
    EXPECT_NEAR(*again + planner->task().PlanCost(theta.data(), theta, false), cost,
                1e-9 * (1 + std::abs(cost)));
    const std::vector<double> logged = LoggedArray(lines[i], "outcome");
    ASSERT_EQ(logged.size(), outcome.size());
    for (size_t k = 0; k < outcome.size(); ++k) {
      if (std::isfinite(outcome[k])) {
        EXPECT_NEAR(logged[k], outcome[k], 1e-9);
      }
    }
  }
  EXPECT_LE(lowest, plain.best_cost);  // the incumbent is among the rescue's candidates
  EXPECT_NEAR(lowest, planner->last_replan().best_cost, 1e-9 * (1 + lowest));
}

// rescue.decay_half_fixed_only: a half-fixed re-plan (warm start above cost_above, best plan
// between half_fixed_above and cost_above) is rescued with the decayed population, trouble above
// cost_above with the full one; the rollout counts of a rescue with and without the decay are the
// independent path.
TEST_F(SoccerPlannerTest, ADecayConfinedToHalfFixedTroubleLeavesNewTroubleTheFullRescue) {
  config::PlannerConfig& p = *config_.run.mutable_planner();
  p.set_prune(false);  // every candidate a whole rollout: the counts below are exact
  config::RescueSearch& rescue = *p.mutable_rescue();
  rescue.set_samples(24);
  rescue.set_iterations(3);
  std::unique_ptr<SoccerPlanner> planner;
  auto plan_once = [&]() { return PlanOnce(0.12, &planner); };
  rescue.set_cost_above(0);
  const ReplanReport plain = plan_once();
  const int64_t plain_rollouts = planner->totals().rollouts;
  const double warm = plain.incumbent_cost, best = plain.best_cost;
  ASSERT_LT(2 * best, warm) << "the ball 12 cm ahead: the search should more than halve the "
                               "warm start's cost";
  // The rescue's rollouts, full and decayed, for new trouble (every re-plan above the bar).
  rescue.set_cost_above(1e-9);
  plan_once();
  const int64_t full_rescue = planner->totals().rollouts - plain_rollouts;
  rescue.set_population_decay(2);
  plan_once();
  const int64_t decayed_rescue = planner->totals().rollouts - plain_rollouts;
  ASSERT_LT(decayed_rescue, full_rescue);
  EXPECT_EQ(planner->totals().half_fixed_rescues, 0);

  rescue.set_decay_half_fixed_only(true);
  rescue.set_half_fixed_above(0.5 * best);
  rescue.set_cost_above(1e-9 + 0.5 * best);  // the best plan above cost_above: new trouble
  EXPECT_TRUE(plan_once().rescued);
  EXPECT_EQ(planner->totals().half_fixed_rescues, 0);
  EXPECT_EQ(planner->totals().rollouts - plain_rollouts, full_rescue);
  rescue.set_cost_above(0.5 * (best + warm));  // the best plan between the bars: half-fixed
  EXPECT_TRUE(plan_once().rescued);
  EXPECT_EQ(planner->totals().half_fixed_rescues, 1);
  EXPECT_EQ(planner->totals().rollouts - plain_rollouts, decayed_rescue);
}

// rescue.refine_first: a troubled re-plan first takes Levenberg–Marquardt steps on the next
// kick, the same steps as the refinement after the search (refine_iterations, the independent
// path here), and runs the wide search only if the plan is still above cost_above.
TEST_F(SoccerPlannerTest, ARefinementBeforeTheRescueSkipsItOnlyWhenItLeavesTrouble) {
  config::PlannerConfig& p = *config_.run.mutable_planner();
  config::RescueSearch& rescue = *p.mutable_rescue();
  rescue.set_samples(24);
  rescue.set_iterations(3);
  const double ahead = 0.06;  // (at 0.12 m the regular search's kick is already a minimum)
  auto plan_once = [&](std::unique_ptr<SoccerPlanner>* planner) { return PlanOnce(ahead, planner); };
  // The regular search alone, and followed by two refinement steps.
  rescue.set_cost_above(0);
  std::unique_ptr<SoccerPlanner> planner;
  const ReplanReport searched = plan_once(&planner);
  p.set_refine_iterations(2);
  const ReplanReport refined = plan_once(&planner);
  const std::vector<double> refined_plan = planner->plan();
  p.set_refine_iterations(0);
  ASSERT_LT(refined.best_cost, searched.best_cost) << "the ball 6 cm ahead leaves room to refine";

  // In trouble (above the threshold) and brought out of it by the refinement: no rescue.
  rescue.set_refine_first(2);
  rescue.set_cost_above(0.5 * (searched.best_cost + refined.best_cost));
  const ReplanReport out = plan_once(&planner);
  EXPECT_FALSE(out.rescued);
  EXPECT_TRUE(out.refined_out);
  EXPECT_EQ(planner->totals().refined_out_of_trouble, 1);
  EXPECT_EQ(planner->totals().rescues, 0);
  EXPECT_EQ(out.best_cost, refined.best_cost);
  EXPECT_EQ(planner->plan(), refined_plan);

  // Still in trouble after it: the rescue runs from the refined plan and can only lower its cost.
  rescue.set_cost_above(0.5 * refined.best_cost);
  const ReplanReport still = plan_once(&planner);
  EXPECT_TRUE(still.rescued);
  EXPECT_FALSE(still.refined_out);
  EXPECT_EQ(planner->totals().refined_out_of_trouble, 0);
  EXPECT_LE(still.best_cost, refined.best_cost);

  // Below the threshold nothing extra runs: the plan is the regular search's.
  rescue.set_cost_above(2 * searched.best_cost);
  const ReplanReport healthy = plan_once(&planner);
  EXPECT_FALSE(healthy.rescued || healthy.refined_out);
  EXPECT_EQ(healthy.best_cost, searched.best_cost);
}

// rescue.half_fixed_above: after a warm start in trouble (above cost_above), a best plan below
// cost_above but above the lower bar is in trouble too; after a healthy warm start the lower bar
// does not apply. The warm start's and the best plan's costs come from a re-plan without rescue.
TEST_F(SoccerPlannerTest, AHalfFixedBarRescuesOnlyAfterAWarmStartInTrouble) {
  config::PlannerConfig& p = *config_.run.mutable_planner();
  config::RescueSearch& rescue = *p.mutable_rescue();
  rescue.set_samples(8);
  rescue.set_iterations(1);
  std::unique_ptr<SoccerPlanner> planner;
  auto plan_once = [&]() { return PlanOnce(0.12, &planner); };
  rescue.set_cost_above(0);
  const ReplanReport plain = plan_once();
  const double warm = plain.incumbent_cost, best = plain.best_cost;
  ASSERT_LT(2 * best, warm) << "the ball 12 cm ahead: the search should more than halve the "
                               "warm start's cost";

  // The warm start in trouble, the best plan out of it by cost_above.
  rescue.set_cost_above(0.5 * (best + warm));
  EXPECT_FALSE(plan_once().rescued) << "no lower bar";
  rescue.set_half_fixed_above(0.5 * best);
  EXPECT_TRUE(plan_once().rescued) << "best " << best << " above the bar " << 0.5 * best;
  rescue.set_half_fixed_above(0.5 * (best + rescue.cost_above()));
  EXPECT_FALSE(plan_once().rescued) << "best " << best << " below the bar";

  // A healthy warm start: the lower bar does not apply.
  rescue.set_cost_above(2 * warm);
  rescue.set_half_fixed_above(0.5 * best);
  EXPECT_FALSE(plan_once().rescued);
}

// With rescue.body the whole-body knots move only in rescues: a planner that never rescues
// keeps them at 0, one that always does moves them.
TEST_F(SoccerPlannerTest, RescueBodyKnotsMoveOnlyInARescue) {
  config::PlannerConfig& p = *config_.run.mutable_planner();
  p.set_body_knot_steps(8);
  p.mutable_rescue()->set_body(true);
  p.mutable_rescue()->set_samples(16);
  p.mutable_rescue()->set_iterations(2);
  p.mutable_rescue()->set_sigma_scale(0.2);  // small corrections: some lower the cost
  for (const double cost_above : {1e30, 1e-9}) {
    p.mutable_rescue()->set_cost_above(cost_above);
    std::unique_ptr<JuggleEnv> env = StartWithBallAhead(0.03);
    std::unique_ptr<SoccerPlanner> planner = NewPlanner();
    float action[kNumActions];
    for (int t = 0; t < 9; ++t) {  // three re-plans
      ASSERT_TRUE(planner->Act(*env, action).ok());
      ASSERT_EQ(env->Step(action, *walk_).outcome, Outcome::kRunning);
    }
    const SoccerPlanLayout& layout = planner->layout();
    double body = 0, kick = 0;
    for (int v = 0; v < layout.dim(); ++v) {
      (v < layout.kick_dim() ? kick : body) += std::abs(planner->plan()[v]);
    }
    EXPECT_GT(kick, 0) << "cost_above " << cost_above;
    if (cost_above > 1) {
      EXPECT_EQ(body, 0);
      EXPECT_EQ(planner->totals().rescues, 0);
    } else {
      EXPECT_GT(body, 0);
      EXPECT_EQ(planner->totals().rescues, 3);
    }
  }
}

// With warm_start_from_executed, a planner whose env was stepped with another action than its
// own moves its kick variables toward those that give the applied action at that state; off,
// the plan stays as it was.
TEST_F(SoccerPlannerTest, WarmStartFromExecutedFollowsTheAppliedAction) {
  config_.run.mutable_planner()->set_replan_every(8);  // no re-plan in the steps checked
  for (const bool follow : {false, true}) {
    config_.run.mutable_planner()->set_warm_start_from_executed(follow);
    std::unique_ptr<JuggleEnv> env = StartWithBallAhead(0.03);
    std::unique_ptr<SoccerPlanner> planner = NewPlanner();
    float own[kNumActions];
    // Into the swing, where the kick variables act; the planner drives.
    int t = 0;
    for (; t < 8; ++t) {
      ASSERT_TRUE(planner->Act(*env, own).ok());
      ASSERT_EQ(env->Step(own, *walk_).outcome, Outcome::kRunning);
    }
    ASSERT_TRUE(planner->Act(*env, own).ok());  // a re-plan (step 8)
    const std::vector<double> plan = planner->plan();
    JuggleEnv previous(spec_, Rng(0));  // the state acted in, for the map afterwards
    ASSERT_TRUE(previous.Restore(*env->Snapshot()).ok());
    // Another action is applied: the plan with a larger hip amplitude.
    std::vector<double> other = plan;
    other[1] += 0.05;
    float applied[kNumActions];
    const PlanClock now{env->steps() - KnotAtOrBefore(planner->layout(), env->steps()), 0};
    SoccerPlanAction(*env, planner->layout(), other.data(), now, applied);
    double moved_by = 0;
    for (int a = 0; a < kNumActions; ++a) moved_by += std::abs(applied[a] - own[a]);
    ASSERT_GT(moved_by, 1e-3) << "the hip amplitude should act at this state";
    ASSERT_EQ(env->Step(applied, *walk_).outcome, Outcome::kRunning);
    ASSERT_TRUE(planner->Act(*env, own).ok());  // no re-plan: step 9
    ASSERT_EQ(planner->last_replan().env_step, 8);
    if (!follow) {
      EXPECT_EQ(planner->plan(), plan);
      continue;
    }
    // The moved plan, at the state it was applied in, gives nearly the applied action.
    float now_gives[kNumActions];
    SoccerPlanAction(previous, planner->layout(), planner->plan().data(), now, now_gives);
    double residual = 0;
    for (int a = 0; a < kNumActions; ++a) residual += std::abs(applied[a] - now_gives[a]);
    EXPECT_LT(residual, 0.3 * moved_by);
    EXPECT_GT(planner->plan()[1] - plan[1], 0) << "the hip amplitude grows toward +0.05";
  }
}

// Σ |change| of the plan's kick variables between successive re-plans over `steps` steps.
double KickChurn(SoccerPlanner* planner, JuggleEnv* env, const AdaptiveWalk& walk, int steps) {
  float action[kNumActions];
  std::vector<double> previous;
  double churn = 0;
  for (int t = 0; t < steps; ++t) {
    EXPECT_TRUE(planner->Act(*env, action).ok());
    if (planner->last_replan().env_step == env->steps()) {
      const std::vector<double> kick(planner->plan().begin(),
                                     planner->plan().begin() + kKickVariables);
      for (size_t v = 0; !previous.empty() && v < kick.size(); ++v) {
        churn += std::abs(kick[v] - previous[v]);
      }
      previous = kick;
    }
    if (env->Step(action, walk).outcome != Outcome::kRunning) break;
  }
  return churn;
}

TEST_F(SoccerPlannerTest, AKickConsistencyTermKeepsRePlansNearTheWarmStart) {
  std::unique_ptr<JuggleEnv> free_env = StartWithBallAhead(0.03);
  const double free_churn = KickChurn(NewPlanner().get(), free_env.get(), *walk_, 24);
  config_.run.mutable_planner()->mutable_soccer_juggle()->mutable_cost()->set_kick_consistency(1e4);
  std::unique_ptr<JuggleEnv> env = StartWithBallAhead(0.03);
  const double held_churn = KickChurn(NewPlanner().get(), env.get(), *walk_, 24);
  EXPECT_GT(free_churn, 0.01);
  EXPECT_LT(held_churn, free_churn / 10) << "free " << free_churn;
}

// cold_start: a re-plan's answer depends on the state only. A planner that drove the episode to
// step 12 and a fresh one asked at that state give the same action; with warm starts they do
// not (the driver's plan carries its history).
TEST_F(SoccerPlannerTest, AColdStartLabelIsAFunctionOfTheStateNotOfThePlansHistory) {
  config_.run.mutable_planner()->set_replan_every(3);
  for (const bool cold : {false, true}) {
    config_.run.mutable_planner()->set_cold_start(cold);
    std::unique_ptr<JuggleEnv> env = StartWithBallAhead(0.03);
    std::unique_ptr<SoccerPlanner> driver = NewPlanner();
    float action[kNumActions];
    for (int t = 0; t < 12; ++t) {
      ASSERT_TRUE(driver->Act(*env, action).ok());
      ASSERT_EQ(env->Step(action, *walk_).outcome, Outcome::kRunning);
    }
    ASSERT_TRUE(driver->Act(*env, action).ok());
    ASSERT_EQ(driver->last_replan().env_step, 12);
    float fresh[kNumActions];
    ASSERT_TRUE(NewPlanner()->Act(*env, fresh).ok());
    double differs = 0;
    for (int a = 0; a < kNumActions; ++a) differs += std::abs(fresh[a] - action[a]);
    if (cold) {
      EXPECT_EQ(differs, 0);
    } else {
      EXPECT_GT(differs, 1e-4) << "a warm-started re-plan should carry its history";
    }
  }
}

// kick_prior: among kicks that land alike the search settles on smaller changes of the swing.
TEST_F(SoccerPlannerTest, AKickPriorShrinksTheChosenKickVariables) {
  auto kick_size = [&](double prior) {
    config_.run.mutable_planner()->mutable_soccer_juggle()->mutable_cost()->set_kick_prior(prior);
    config_.run.mutable_planner()->set_refine_iterations(2);
    std::unique_ptr<JuggleEnv> env = StartWithBallAhead(0.06);
    std::unique_ptr<SoccerPlanner> planner = NewPlanner();
    float action[kNumActions];
    EXPECT_TRUE(planner->Act(*env, action).ok());
    // In units of the search spreads (the prior's units).
    const config::KickVariables& k = config_.run.planner().soccer_juggle().kick();
    double size = std::pow(planner->plan()[0] / k.phase_sigma_s(), 2);
    for (int v = 1; v < kKickVariables; ++v) size += std::pow(planner->plan()[v] / k.angle_sigma(), 2);
    return std::sqrt(size);
  };
  const double free = kick_size(0);
  const double held = kick_size(100);
  // The ball 6 cm ahead needs a kick change of about two spreads; the prior gives up some landing
  // for a smaller one (measured: 2.3 spreads free, 1.4 at prior 100).
  EXPECT_GT(free, 1);
  EXPECT_LT(held, 0.75 * free) << "free " << free;
}

// PlannerConfig.robust: the search scores a candidate by the mean of its noiseless rollout and
// its noisy draws (each re-evaluated here on its own), while its prediction stays noiseless.
TEST_F(SoccerPlannerTest, ARobustPlanCostsTheMeanOfItsNoiselessAndNoisyRollouts) {
  config::RobustCost& robust = *config_.run.mutable_planner()->mutable_robust();
  robust.set_draws(2);
  robust.set_action_noise(0.05);
  robust.set_hold_steps(3);
  config_.run.mutable_planner()->mutable_rescue()->set_cost_above(0);  // one search, quicker
  std::unique_ptr<JuggleEnv> env = StartWithBallAhead(0.03);
  std::unique_ptr<SoccerPlanner> planner = NewPlanner();
  float action[kNumActions];
  ASSERT_TRUE(planner->Act(*env, action).ok());
  const std::vector<double> plan = planner->plan();
  KickOutcome kick;
  absl::StatusOr<double> noiseless = planner->Evaluate(*env, plan, &kick);
  absl::StatusOr<double> first = planner->Evaluate(*env, plan, nullptr, 1);
  absl::StatusOr<double> second = planner->Evaluate(*env, plan, nullptr, 2);
  ASSERT_TRUE(noiseless.ok() && first.ok() && second.ok());
  EXPECT_NE(*first, *noiseless);
  EXPECT_NE(*second, *first);
  EXPECT_DOUBLE_EQ(planner->last_replan().best_cost, (*noiseless + *first + *second) / 3);
  ASSERT_TRUE(kick.valid);
  EXPECT_EQ(PredictedKick(planner->last_replan()).timing, kick.timing);
  EXPECT_EQ(PredictedKick(planner->last_replan()).dx, kick.dx);
  // Every candidate was simulated three times, and the chosen plan once more for its prediction.
  EXPECT_EQ(planner->totals().rollouts, 3 * planner->last_replan().evaluations + 1);
}

// The robust draws have their own random streams: with zero noise they change no plan.
TEST_F(SoccerPlannerTest, RobustDrawsWithoutNoiseChooseTheSamePlans) {
  std::vector<std::vector<float>> runs;
  for (int draws : {0, 2}) {
    config::RobustCost& robust = *config_.run.mutable_planner()->mutable_robust();
    robust.set_draws(draws);
    robust.set_action_noise(0);
    config_.run.mutable_planner()->set_prune(false);  // robust draws never prune
    std::unique_ptr<JuggleEnv> env = StartWithBallAhead(0.03);
    runs.push_back(ActionsOver(NewPlanner().get(), env.get(), *walk_, 10));
  }
  EXPECT_EQ(runs[0], runs[1]);
}

TEST_F(SoccerPlannerTest, LaterKicksByBaseActWithoutKickVariablesPastThePlansSets) {
  config::PlannerConfig p = config_.run.planner();
  p.mutable_soccer_juggle()->mutable_kick()->set_later_kicks_by_base(true);
  const SoccerPlanLayout by_base = MakeSoccerPlanLayout(p, p.soccer_juggle().kick());
  p.mutable_soccer_juggle()->mutable_kick()->set_later_kicks_by_base(false);
  const SoccerPlanLayout repeated = MakeSoccerPlanLayout(p, p.soccer_juggle().kick());
  ASSERT_EQ(by_base.kick_sets, 1);
  const std::vector<double> theta = {0.03, 0.2, -0.15, 0.25, -0.1};
  const std::vector<double> zero(theta.size(), 0.0);
  std::unique_ptr<JuggleEnv> env = StartWithBallAhead(0);
  const float still[kNumActions] = {0};
  int differing = 0;
  for (int step = 0; step < 30; ++step) {
    float first[kNumActions], later[kNumActions], plain[kNumActions], again[kNumActions];
    SoccerPlanAction(*env, by_base, theta.data(), {step, 0}, first);
    SoccerPlanAction(*env, by_base, theta.data(), {step, 1}, later);
    SoccerPlanAction(*env, by_base, zero.data(), {step, 1}, plain);
    SoccerPlanAction(*env, repeated, theta.data(), {step, 1}, again);
    bool differs = false;
    for (int i = 0; i < kNumActions; ++i) {
      ASSERT_EQ(later[i], plain[i]) << "step " << step << " action " << i;
      ASSERT_EQ(again[i], first[i]) << "step " << step << " action " << i;
      differs = differs || first[i] != plain[i];
    }
    differing += differs;
    ASSERT_EQ(env->Step(still, *walk_).outcome, Outcome::kRunning);
  }
  // The variables act in the plan's own cycle, so the equalities above compare something.
  EXPECT_GT(differing, 10);
}

TEST_F(SoccerPlannerTest, AShiftedPlanActsAsBefore) {
  config::PlannerConfig p = config_.run.planner();
  p.set_body_knot_steps(5);
  p.set_horizon_steps(20);
  const SoccerPlanLayout layout = MakeSoccerPlanLayout(p, p.soccer_juggle().kick());
  ASSERT_GT(layout.body_knots, 2);
  Rng rng(2);
  std::vector<double> theta(layout.dim());
  for (double& x : theta) x = rng.Uniform(-0.3, 0.3);
  std::unique_ptr<JuggleEnv> env = StartWithBallAhead(0);
  const std::vector<double> shifted = ShiftSoccerPlan(layout, theta, 1, 0);
  float a[kNumActions], b[kNumActions];
  // Steps 5..19 of the old plan are steps 0..14 of the one shifted by one knot.
  for (int step = 5; step < 20; ++step) {
    SoccerPlanAction(*env, layout, theta.data(), {step, 0}, a);
    SoccerPlanAction(*env, layout, shifted.data(), {step - 5, 0}, b);
    for (int i = 0; i < kNumActions; ++i) ASSERT_EQ(a[i], b[i]) << "step " << step;
  }
}

}  // namespace
}  // namespace juggle::planner

namespace juggle::planner {
namespace {

// A fork on the planner's own stream plans like the planner (the search is deterministic per
// stream); on another stream its next re-plan differs — the label spread of
// planner/label_spread.h compares such forks.
TEST_F(SoccerPlannerTest, AForkOnItsOwnStreamActsAlikeAndOnAnotherStreamDiffers) {
  std::unique_ptr<JuggleEnv> env = StartWithBallAhead(0.0);
  std::unique_ptr<SoccerPlanner> planner = NewPlanner();
  float a[kNumActions];
  ASSERT_TRUE(planner->Act(*env, a).ok());
  ASSERT_EQ(env->Step(a, *walk_).outcome, Outcome::kRunning);
  // Next step the plan is followed; step to the next re-plan (every 4 steps).
  for (int k = 1; k < 4; ++k) {
    ASSERT_TRUE(planner->Act(*env, a).ok());
    ASSERT_EQ(env->Step(a, *walk_).outcome, Outcome::kRunning);
  }
  RecedingHorizonPlanner same = planner->Fork(0), other = planner->Fork(77);
  float a_same[kNumActions], a_other[kNumActions];
  ASSERT_TRUE(planner->Act(*env, a).ok());
  ASSERT_EQ(planner->last_replan().env_step, env->steps()) << "a re-plan was due";
  ASSERT_TRUE(same.Act(*env, a_same).ok());
  ASSERT_TRUE(other.Act(*env, a_other).ok());
  double same_diff = 0, other_diff = 0;
  for (int i = 0; i < kNumActions; ++i) {
    same_diff += std::abs(a[i] - a_same[i]);
    other_diff += std::abs(a[i] - a_other[i]);
  }
  EXPECT_EQ(same_diff, 0.0);
  EXPECT_GT(other_diff, 0.0);
}

}  // namespace
}  // namespace juggle::planner

namespace juggle::planner {
namespace {

// A joint whose feed-forward scale is 0 ignores its actions; the planner's actions (the
// workers' labels) there are 0, not kp/0 · 0 = NaN, which the learner would refuse as
// non-finite labels (configs/learning/guided_leg_only.textproto masks joints this way).
TEST(SoccerPlannerMaskTest, JointsWithZeroFeedForwardScaleGetZeroFiniteActions) {
  absl::StatusOr<LoadedConfig> config =
      LoadRunConfig(::juggle::testing::RepoPath("configs/right_foot_planner.textproto"));
  ASSERT_TRUE(config.ok()) << config.status();
  config::JointGains* chest = config->run.mutable_soccer_juggle()->mutable_env()->add_joint_gains();
  chest->set_joint("chest");
  chest->set_torque_scale(0);
  config::PlannerConfig& p = *config->run.mutable_planner();
  p.set_samples(8);
  p.set_iterations(1);
  absl::StatusOr<std::shared_ptr<const EnvSpec>> spec = CreateEnvSpec(*config);
  ASSERT_TRUE(spec.ok()) << spec.status();
  auto soccer = std::dynamic_pointer_cast<const JuggleSpec>(*spec);
  RolloutPool pool(soccer, 1);
  SoccerPlanner planner(soccer, p, &pool, 0);
  JuggleEnv env(soccer, Rng(5));
  AdaptiveWalk walk(&soccer->graph());
  env.Reset(walk);
  float a[kNumActions];
  for (int k = 0; k < 20; ++k) {
    ASSERT_TRUE(planner.Act(env, a).ok());
    for (int i = 0; i < kNumActions; ++i) ASSERT_TRUE(std::isfinite(a[i])) << "step " << k;
    EXPECT_EQ(a[0], 0.0f);  // the chest's three actions
    EXPECT_EQ(a[1], 0.0f);
    EXPECT_EQ(a[2], 0.0f);
    if (env.Step(a, walk).outcome != Outcome::kRunning) break;
  }
}

// Every body's centre-of-mass velocity (3 per body, world axes) from a fresh forward pass on a
// copy of `d`: the spatial velocities at the step's end.
std::vector<double> VelocitiesAfterForward(const mjModel* m, const mjData* d) {
  mjData* copy = mj_copyData(nullptr, m, d);
  mj_forward(m, copy);
  std::vector<double> v(3 * m->nbody, 0.0);
  for (int b = 1; b < m->nbody; ++b) {
    double spatial[6];
    mj_objectVelocity(m, copy, mjOBJ_BODY, b, spatial, 0);
    mju_copy3(v.data() + 3 * b, spatial + 3);
  }
  mj_deleteData(copy);
  return v;
}

// ImpactTracker (the impact acceleration) agrees with the kicking foot's velocity from a separate
// forward pass, and a tracker begun one step before the touch measures it too.
TEST_F(SoccerPlannerTest, ImpactAccelerationAgreesWithTheFootsVelocityFromAForwardPass) {
  const mjModel* m = spec_->model();
  const double dt = spec_->control_dt();
  const float zero[kNumActions] = {0};
  int measured = 0;
  std::vector<uint64_t> touch_seeds;
  std::vector<int> touch_steps;
  std::vector<double> impacts;
  for (uint64_t seed = 1; seed <= 4; ++seed) {
    std::unique_ptr<JuggleEnv> env = StartWithBallAhead(0.0, seed);
    ImpactTracker tracker;
    tracker.Begin(*env);
    std::vector<std::vector<double>> velocities = {VelocitiesAfterForward(m, env->data())};
    std::vector<double> ball = {env->data()->qvel + spec_->ball_dof(),
                                env->data()->qvel + spec_->ball_dof() + 3};
    for (int t = 0; t < 60; ++t) {
      const bool touched_before = env->state().kick_touched;
      if (env->Step(zero, *walk_).outcome != Outcome::kRunning) break;
      const double impact = tracker.AfterStep(*env);
      const mjData* d = env->data();
      if (env->state().kick_touched && !touched_before) {
        ASSERT_TRUE(std::isfinite(impact)) << "seed " << seed << " step " << t;
        touch_seeds.push_back(seed);
        touch_steps.push_back(t);
        impacts.push_back(impact);
        // The impulse's direction from the ball's velocity change, gravity taken out.
        double n[3];
        for (int i = 0; i < 3; ++i) n[i] = d->qvel[spec_->ball_dof() + i] - ball[i];
        n[2] += spec_->env().gravity() * dt;
        mju_normalize3(n);
        EXPECT_GT(n[2], 0.5) << "a foot kick sends the ball up";
        // The touching body: the foot (the node also allows the shin, which a kick from the
        // apex start does not use).
        const int body = mj_name2id(m, mjOBJ_BODY, "right_ankle");
        ASSERT_GT(body, 0);
        EXPECT_EQ(env->state().touched_body, body);
        const std::vector<double>& one = velocities[velocities.size() - 1];
        const std::vector<double>& two = velocities[velocities.size() - 2];
        double expected = 0;
        for (int i = 0; i < 3; ++i) expected += (one[3 * body + i] - two[3 * body + i]) * n[i];
        expected /= dt;
        // The tracker's Jacobians are of the last substep's start, one substep earlier.
        EXPECT_NEAR(impact, expected, 0.02 * std::abs(expected) + 0.2) << "seed " << seed;
        EXPECT_LT(impact, 0) << "the base controller's swing meets the ball decelerating";
        ++measured;
        break;
      }
      EXPECT_FALSE(std::isfinite(impact)) << "no first touch at step " << t;
      velocities.push_back(VelocitiesAfterForward(m, d));
      ball.assign(d->qvel + spec_->ball_dof(), d->qvel + spec_->ball_dof() + 3);
    }
  }
  EXPECT_GE(measured, 3) << "the base controller kicks from most apex starts";

  // A tracker begun one step before the touch (history from the state's acceleration) measures
  // the same kick nearly alike.
  for (size_t k = 0; k < touch_steps.size(); ++k) {
    std::unique_ptr<JuggleEnv> env = StartWithBallAhead(0.0, touch_seeds[k]);
    for (int t = 0; t < touch_steps[k]; ++t) {
      ASSERT_EQ(env->Step(zero, *walk_).outcome, Outcome::kRunning);
    }
    ImpactTracker late;
    late.Begin(*env);
    env->Step(zero, *walk_);
    EXPECT_NEAR(late.AfterStep(*env), impacts[k], 0.1 * std::abs(impacts[k]) + 0.5)
        << "seed " << touch_seeds[k];
  }
}

// The cost adds weight × (distance outside [min, max] / scale)² for the kick, nothing inside.
TEST_F(SoccerPlannerTest, ImpactAccelerationCostIsTheSquaredDistanceOutsideItsBandPerKick) {
  std::unique_ptr<JuggleEnv> env = StartWithBallAhead(0.0, 3);
  auto cost_of_zero_plan = [&](double weight, double min, double max, KickOutcome* kick) {
    config::PlannerCost& cost = *config_.run.mutable_planner()->mutable_soccer_juggle()->mutable_cost();
    cost.set_impact_acceleration(weight);
    cost.set_impact_acceleration_min(min);
    cost.set_impact_acceleration_max(max);
    cost.set_impact_acceleration_scale(4);
    SoccerPlanner planner(spec_, config_.run.planner(), pool_.get(), 0);
    const std::vector<double> zero(planner.layout().dim(), 0.0);
    absl::StatusOr<double> c = planner.Evaluate(*env, zero, kick);
    EXPECT_TRUE(c.ok()) << c.status();
    return c.value_or(0);
  };
  KickOutcome kick;
  const double free = cost_of_zero_plan(0, -1000, 0, &kick);
  ASSERT_TRUE(kick.valid);
  const double a = kick.impact_acceleration;
  ASSERT_TRUE(std::isfinite(a));
  ASSERT_LT(free, 1e4) << "the zero plan kicks without failing inside the horizon";
  const double tolerance = 1e-6;
  EXPECT_NEAR(cost_of_zero_plan(7, -1000, a - 2, &kick) - free, 7 * 0.25, tolerance);
  EXPECT_NEAR(cost_of_zero_plan(7, a + 6, 1000, &kick) - free, 7 * 2.25, tolerance);
  EXPECT_NEAR(cost_of_zero_plan(7, a - 1, a + 1, &kick) - free, 0, tolerance);
}

TEST_F(SoccerPlannerTest, ImpactObserverReportsEveryExecutedKickAsATrackerSteppedAlongside) {
  EpisodeOptions options;
  options.episodes = 3;
  options.seed = 77;
  options.start_node = down_;
  ZeroController zero_controller(kNumActions);
  absl::StatusOr<EpisodeReport> plain = RunEpisodes(spec_, &zero_controller, options);
  ASSERT_TRUE(plain.ok()) << plain.status();
  ImpactObservingController observed(&zero_controller);
  absl::StatusOr<EpisodeReport> report = RunEpisodes(spec_, &observed, options);
  ASSERT_TRUE(report.ok()) << report.status();
  EXPECT_EQ(observed.envs_measured(), 3);
  // Observing changes no action: the same episodes.
  for (int i = 0; i < 3; ++i) {
    EXPECT_EQ(report->episodes[i].steps, plain->episodes[i].steps) << "episode " << i;
    EXPECT_EQ(report->episodes[i].juggles, plain->episodes[i].juggles) << "episode " << i;
  }
  // The same episodes stepped by hand with a tracker; the step that ends an episode is not
  // measured by the observer.
  std::vector<double> expected;
  const float zero[kNumActions] = {0};
  for (int i = 0; i < 3; ++i) {
    JuggleEnv env(spec_, Rng::ForStream(77, 0, i));
    ASSERT_TRUE(env.ResetAt(down_, *walk_));
    ImpactTracker tracker;
    tracker.Begin(env);
    while (env.Step(zero, *walk_).outcome == Outcome::kRunning) {
      const double a = tracker.AfterStep(env);
      if (std::isfinite(a)) expected.push_back(a);
    }
  }
  ASSERT_FALSE(expected.empty()) << "zero action kicks at least once from an apex start";
  std::vector<double> got = observed.accelerations();
  std::sort(got.begin(), got.end());
  std::sort(expected.begin(), expected.end());
  EXPECT_EQ(got, expected);
}

TEST(ImpactSummaryTest, ReportsThePercentilesAndTheShareInsideTheBand) {
  EXPECT_EQ(ImpactSummary({}, -9.9, 0), " impact_kicks=0");
  EXPECT_EQ(ImpactSummary({-12, -5, -3, 1}, -9.9, 0),
            " impact_kicks=4 impact_p10=-9.90 impact_median=-4.00 impact_p90=-0.20 "
            "impact_in_band=0.500");
}

}  // namespace
}  // namespace juggle::planner

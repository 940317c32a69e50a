// A held follow-through (KickVariables.hold_follow_through) and the shared prefix it allows
// (PlannerConfig.share_prefix): after a release the leg's way back follows the kick it left
// with, whatever the plan's set becomes; the set acts again from the next cycle; and simulating
// the steps where no variable acts once per re-plan chooses the same plans, predicted bit for
// bit, from fewer rollout steps; a kick ramp (KickVariables.act_from_phase) shares the steps
// before its phase the same way.
#include <algorithm>
#include <cstdint>
#include <memory>
#include <vector>

#include "envs/registry.h"
#include "envs/testing/test_configs.h"
#include "gtest/gtest.h"
#include "planner/receding_horizon.h"
#include "planner/soccer_juggle/plan.h"
#include "planner/soccer_juggle/task.h"
#include "planner/soccer_juggle/test_kicks.h"

namespace juggle::planner {
namespace {

using soccer_juggle::JuggleEnv;
using soccer_juggle::JuggleSpec;
using soccer_juggle::kNumActions;

class SharedPrefixTest : public ::testing::Test {
 protected:
  void SetUp() override {
    absl::StatusOr<LoadedConfig> config = SmallRightFootPlanner();
    ASSERT_TRUE(config.ok()) << config.status();
    config_ = *config;
    config_.run.mutable_planner()->mutable_soccer_juggle()->mutable_kick()->set_hold_follow_through(
        true);
    absl::StatusOr<std::shared_ptr<const EnvSpec>> spec = CreateEnvSpec(config_);
    ASSERT_TRUE(spec.ok()) << spec.status();
    spec_ = std::dynamic_pointer_cast<const JuggleSpec>(*spec);
    walk_ = std::make_unique<AdaptiveWalk>(&spec_->graph());
    pool_ = std::make_unique<RolloutPool>(spec_, 2);
  }

  // An env at the apex of right_foot_down with the ball 3 cm ahead of its target.
  std::unique_ptr<JuggleEnv> Start() {
    auto env = std::make_unique<JuggleEnv>(spec_, Rng(3));
    env->ResetAt(*spec_->graph().FindNode("right_foot_down"), *walk_);
    env->data()->qpos[spec_->ball_qpos()] += 0.03;
    mj_forward(spec_->model(), env->data());
    return env;
  }

  SoccerJuggleTask Task() const { return SoccerJuggleTask(spec_, config_.run.planner()); }

  // The planner with settings `p` over 30 control steps from Start() (the kick's release at
  // about step 20), or until the episode ends: its totals.
  PlannerTotals PlanThirtySteps(const config::PlannerConfig& p) {
    RecedingHorizonPlanner planner(std::make_shared<SoccerJuggleTask>(spec_, p), p, pool_.get(), 0);
    std::unique_ptr<JuggleEnv> env = Start();
    float action[kNumActions];
    for (int t = 0; t < 30; ++t) {
      EXPECT_TRUE(planner.Act(*env, action).ok());
      if (env->Step(action, *walk_).outcome != Outcome::kRunning) break;
    }
    return planner.totals();
  }

  LoadedConfig config_;
  std::shared_ptr<const JuggleSpec> spec_;
  std::unique_ptr<AdaptiveWalk> walk_;
  std::unique_ptr<RolloutPool> pool_;
};

// A plan with kick set 0 = `kick` and the held kick `held` (flag 1), zero elsewhere.
std::vector<double> PlanWith(const SoccerPlanLayout& layout, const std::vector<double>& kick,
                             const std::vector<double>& held) {
  std::vector<double> theta(layout.dim(), 0.0);
  std::copy(kick.begin(), kick.end(), theta.begin() + layout.kick(0));
  std::copy(held.begin(), held.end(), theta.begin() + layout.held());
  theta[layout.held_count()] = 1;
  return theta;
}

// A kick set the tests' previous plans leave with.
const std::vector<double> kLeftWith = {0.01, 0.1, -0.05, 0.08, 0.04};

// A previous plan, shifted: kick set 0 = kLeftWith, nothing held yet.
std::vector<double> ShiftedLeftWith(const SoccerPlanLayout& layout) {
  std::vector<double> shifted = PlanWith(layout, kLeftWith, std::vector<double>(kKickVariables, 0));
  shifted[layout.held_count()] = 0;
  return shifted;
}

std::vector<float> ActionOf(const JuggleEnv& env, const SoccerPlanLayout& layout,
                            const std::vector<double>& theta, PlanClock clock) {
  std::vector<float> action(kNumActions);
  SoccerPlanAction(env, layout, theta.data(), clock, action.data());
  return action;
}

TEST_F(SharedPrefixTest, AHeldFollowThroughIgnoresTheKickSetUntilTheNextCycle) {
  const SoccerJuggleTask task = Task();
  const SoccerPlanLayout& layout = task.layout();
  ASSERT_EQ(layout.dim(), 2 * kKickVariables + 1);
  std::unique_ptr<JuggleEnv> env = Start();
  ASSERT_TRUE(ZeroActionKick(env.get(), *walk_).valid);  // the kick has left the foot
  const std::vector<double> held = {0.01, 0.1, -0.05, 0.08, 0.04};
  const std::vector<double> a = PlanWith(layout, {0, 0, 0, 0, 0}, held);
  const std::vector<double> b = PlanWith(layout, {-0.02, 0.3, 0.2, -0.3, 0.2}, held);
  // Cycle 0 after the release: the held kick acts, the set does not.
  EXPECT_FALSE(task.PlanActs(*env, b.data(), {0, 0}));
  EXPECT_EQ(ActionOf(*env, layout, a, {0, 0}), ActionOf(*env, layout, b, {0, 0}));
  std::vector<double> other_held = a;
  other_held[layout.held() + 1] += 0.2;
  EXPECT_NE(ActionOf(*env, layout, other_held, {0, 0}), ActionOf(*env, layout, a, {0, 0}));
  // The next cycle: the set acts.
  EXPECT_TRUE(task.PlanActs(*env, b.data(), {0, 1}));
  EXPECT_NE(ActionOf(*env, layout, a, {0, 1}), ActionOf(*env, layout, b, {0, 1}));
  // Without the flag the set acts in cycle 0 as before.
  std::vector<double> unflagged = b;
  unflagged[layout.held_count()] = 0;
  EXPECT_TRUE(task.PlanActs(*env, unflagged.data(), {0, 0}));
  EXPECT_NE(ActionOf(*env, layout, unflagged, {0, 0}), ActionOf(*env, layout, b, {0, 0}));
}

TEST_F(SharedPrefixTest, ARestrictionHoldsTheKickThePreviousPlanLeftWith) {
  const SoccerJuggleTask task = Task();
  const SoccerPlanLayout& layout = task.layout();
  std::unique_ptr<JuggleEnv> env = Start();
  const std::vector<double>& left_with = kLeftWith;
  std::vector<double> shifted = ShiftedLeftWith(layout);
  auto restrict = [&](const std::vector<double>& from) {
    SearchSpace space = task.space();
    std::vector<std::vector<double>> seeds = task.Seeds(from);
    task.Restrict(*env, from, &space, &seeds);
    for (int i = 0; i <= kKickVariables; ++i) {
      const int v = layout.held() + i;
      EXPECT_EQ(space.sigma[v], 0);
      EXPECT_EQ(space.lower[v], space.upper[v]);
      for (const std::vector<double>& seed : seeds) EXPECT_EQ(seed[v], space.lower[v]);
    }
    EXPECT_GT(space.sigma[layout.kick(0) + 1], 0);  // the set is still searched
    return std::vector<double>(space.lower.begin() + layout.held(), space.lower.end());
  };
  // Before the release nothing is held.
  EXPECT_EQ(restrict(shifted), std::vector<double>(kKickVariables + 1, 0.0));
  ASSERT_TRUE(ZeroActionKick(env.get(), *walk_).valid);
  // The first re-plan after it holds the set the previous plan left with ...
  std::vector<double> expected = left_with;
  expected.push_back(1);
  EXPECT_EQ(restrict(shifted), expected);
  // ... and later ones keep that hold whatever the set has become, counting on.
  std::vector<double> later = PlanWith(layout, {0, 0.3, 0, 0, 0}, left_with);
  expected.back() = 2;
  EXPECT_EQ(restrict(later), expected);
  // A new cycle ends the hold.
  const std::vector<double> next_cycle = task.Shift(later, 0, 1);
  EXPECT_EQ(next_cycle[layout.held_count()], 0);
}

// hold_after_replans: the first re-plan after the release still moves the follow-through; the
// next holds what it left with.
TEST_F(SharedPrefixTest, AHoldAfterOneReplanLetsTheFirstReplanAfterTheReleaseMoveTheFollowThrough) {
  config_.run.mutable_planner()->mutable_soccer_juggle()->mutable_kick()->set_hold_after_replans(1);
  const SoccerJuggleTask task = Task();
  const SoccerPlanLayout& layout = task.layout();
  std::unique_ptr<JuggleEnv> env = Start();
  ASSERT_TRUE(ZeroActionKick(env.get(), *walk_).valid);
  const std::vector<double>& first_after = kLeftWith;
  std::vector<double> shifted = ShiftedLeftWith(layout);
  auto restrict = [&](const std::vector<double>& from) {
    SearchSpace space = task.space();
    std::vector<std::vector<double>> seeds = task.Seeds(from);
    task.Restrict(*env, from, &space, &seeds);
    return seeds.front();
  };
  const std::vector<double> first = restrict(std::vector<double>(layout.dim(), 0.0));
  EXPECT_EQ(first[layout.held_count()], 1);
  EXPECT_TRUE(task.PlanActs(*env, first.data(), {0, 0}));  // the set still moves it
  shifted[layout.held_count()] = 1;  // the first re-plan's plan, shifted
  const std::vector<double> second = restrict(shifted);
  EXPECT_EQ(second[layout.held_count()], 2);
  EXPECT_EQ(
      std::vector<double>(second.begin() + layout.held(), second.begin() + layout.held_count()),
      first_after);
  EXPECT_FALSE(task.PlanActs(*env, second.data(), {0, 0}));
}

// hold_in_rescue: a rescue after the release, before the hold, holds what the previous plan
// left with and flags it held; before the release, or once held, it changes nothing.
TEST_F(SharedPrefixTest, ARescueAfterTheReleaseHoldsTheSetThePreviousPlanLeftWith) {
  auto& kick = *config_.run.mutable_planner()->mutable_soccer_juggle()->mutable_kick();
  kick.set_hold_after_replans(1000);
  kick.set_hold_in_rescue(true);
  const SoccerJuggleTask task = Task();
  const SoccerPlanLayout& layout = task.layout();
  std::unique_ptr<JuggleEnv> env = Start();
  const std::vector<double>& left_with = kLeftWith;
  std::vector<double> shifted = ShiftedLeftWith(layout);
  struct Narrowed {
    bool changed;
    SearchSpace space;
    std::vector<std::vector<double>> seeds;
  };
  auto narrow = [&](const std::vector<double>& from) {
    Narrowed n{false, task.space(), task.Seeds(from)};
    task.Restrict(*env, from, &n.space, &n.seeds);
    n.seeds.insert(n.seeds.begin(), std::vector<double>(layout.dim(), 0.3));  // an incumbent
    n.changed = task.RestrictRescue(*env, from, &n.space, &n.seeds);
    return n;
  };
  EXPECT_FALSE(narrow(shifted).changed);  // before the release
  ASSERT_TRUE(ZeroActionKick(env.get(), *walk_).valid);
  const Narrowed after = narrow(shifted);
  ASSERT_TRUE(after.changed);
  std::vector<double> expected = left_with;
  expected.push_back(1001);
  for (int i = 0; i <= kKickVariables; ++i) {
    const int v = layout.held() + i;
    EXPECT_EQ(after.space.sigma[v], 0);
    EXPECT_EQ(after.space.lower[v], expected[i]);
    EXPECT_EQ(after.space.upper[v], expected[i]);
    for (const std::vector<double>& seed : after.seeds) EXPECT_EQ(seed[v], expected[i]);
  }
  EXPECT_GT(after.space.sigma[layout.kick(0) + 1], 0);  // the set is still searched
  EXPECT_FALSE(task.PlanActs(*env, after.seeds.front().data(), {0, 0}));
  // A plan so held, shifted to the next re-plan: the regular search keeps the hold.
  std::vector<double> held_plan = after.seeds.front();
  SearchSpace space = task.space();
  std::vector<std::vector<double>> seeds = task.Seeds(held_plan);
  task.Restrict(*env, held_plan, &space, &seeds);
  EXPECT_EQ(std::vector<double>(space.lower.begin() + layout.held(),
                                space.lower.begin() + layout.held_count()),
            left_with);
  EXPECT_FALSE(task.PlanActs(*env, seeds.front().data(), {0, 0}));
  EXPECT_FALSE(narrow(held_plan).changed);  // held already
}

// A rescue after the release with hold_in_rescue shares the way back: fewer rollout steps than
// the same rescues unheld, the same actions up to the release, every visited state as
// predicted, and from the first rescue that holds on the plan holds.
TEST_F(SharedPrefixTest, ARescueThatHoldsTheFollowThroughSharesItsPrefixAndPredictsExactly) {
  config::PlannerConfig& p = *config_.run.mutable_planner();
  p.set_share_prefix(true);
  p.mutable_soccer_juggle()->mutable_kick()->set_hold_after_replans(1000);
  p.mutable_rescue()->set_cost_above(1e-9);
  p.mutable_rescue()->set_samples(16);
  p.mutable_rescue()->set_iterations(2);
  std::vector<float> actions[2];
  PlannerTotals totals[2];
  int first_held = -1;
  int release = -1;
  for (int arm = 0; arm < 2; ++arm) {
    p.mutable_soccer_juggle()->mutable_kick()->set_hold_in_rescue(arm == 1);
    const auto task = std::make_shared<SoccerJuggleTask>(spec_, p);
    RecedingHorizonPlanner planner(task, p, pool_.get(), 0);
    std::unique_ptr<JuggleEnv> env = Start();
    float action[kNumActions];
    for (int t = 0; t < 44; ++t) {  // the kick at about step 20, then its follow-through
      const bool released = env->state().kick_touched && !env->state().touched_this_step;
      if (arm == 0 && released && release < 0) release = t;
      ASSERT_TRUE(planner.Act(*env, action).ok());
      const std::vector<double>& plan = planner.plan();
      const bool holds = plan[task->layout().held_count()] > task->layout().hold_after;
      if (arm == 0) {
        EXPECT_FALSE(holds) << "step " << t;
      }
      if (arm == 1 && holds && first_held < 0) first_held = t;
      if (arm == 1 && first_held >= 0) {
        EXPECT_TRUE(holds) << "step " << t;  // once held, held to the cycle's end
      }
      actions[arm].insert(actions[arm].end(), action, action + kNumActions);
      ASSERT_EQ(env->Step(action, *walk_).outcome, Outcome::kRunning) << "step " << t;
    }
    totals[arm] = planner.totals();
  }
  ASSERT_GT(release, 10);
  ASSERT_GE(first_held, release) << "the hold starts after the kick's release";
  EXPECT_TRUE(std::equal(actions[1].begin(), actions[1].begin() + release * kNumActions,
                         actions[0].begin()));
  EXPECT_GE(totals[1].prediction_checks, 40);
  EXPECT_EQ(totals[1].prediction_mismatches, 0);
  EXPECT_LT(totals[1].rollout_steps, totals[0].rollout_steps * 0.9)
      << totals[1].rollout_steps << " against " << totals[0].rollout_steps;
}

// full_after_narrowed: a held rescue still in trouble is followed by an unheld one. With a bar
// below every cost each held rescue is followed (more rollouts, every state still as
// predicted); with a bar above every cost, or without the hold, none is.
TEST_F(SharedPrefixTest, AnUnheldRescueFollowsAHeldOneOnlyWhenItEndsInTrouble) {
  config::PlannerConfig& p = *config_.run.mutable_planner();
  p.set_share_prefix(true);
  auto& kick = *p.mutable_soccer_juggle()->mutable_kick();
  kick.set_hold_after_replans(1000);
  p.mutable_rescue()->set_samples(16);
  p.mutable_rescue()->set_iterations(2);
  struct Arm {
    bool hold;
    bool full_after;
    double cost_above;
  };
  auto run = [&](const Arm& arm) {
    kick.set_hold_in_rescue(arm.hold);
    p.mutable_rescue()->set_full_after_narrowed(arm.full_after);
    p.mutable_rescue()->set_cost_above(arm.cost_above);
    return PlanThirtySteps(p);
  };
  // Every re-plan in trouble (a bar below any cost): every held rescue is followed.
  const PlannerTotals held = run({true, false, 1e-9});
  const PlannerTotals cascade = run({true, true, 1e-9});
  EXPECT_GT(cascade.full_after_narrowed, 0);
  EXPECT_EQ(cascade.prediction_mismatches, 0);
  EXPECT_GT(cascade.rollouts, held.rollouts);
  // A bar no plan exceeds: no rescue, nothing followed.
  const PlannerTotals calm = run({true, true, 1e12});
  EXPECT_EQ(calm.rescues, 0);
  EXPECT_EQ(calm.full_after_narrowed, 0);
  // Without the hold nothing is narrowed, so nothing follows.
  const PlannerTotals unheld = run({false, true, 1e-9});
  EXPECT_EQ(unheld.full_after_narrowed, 0);
  EXPECT_GT(unheld.rescues, 0);
}

// narrowed_samples and narrowed_iterations size the held rescue alone. With every re-plan in
// trouble each re-plan rescues and each held rescue is followed by the unheld one, so the
// rollouts differ only by the held searches: a 16 x 2 search scores 16 + 15 candidates (one
// elite carried into the second iteration, planner/cem_search.cc), a 4 x 1 search 4. The
// counts are exact whatever the two episodes do; an unheld follow-up at the narrowed budget, or
// either field ignored, breaks the equality.
TEST_F(SharedPrefixTest, ANarrowedBudgetShrinksTheHeldRescueAndNotItsUnheldFollowUp) {
  config::PlannerConfig& p = *config_.run.mutable_planner();
  p.set_share_prefix(true);
  auto& kick = *p.mutable_soccer_juggle()->mutable_kick();
  kick.set_hold_after_replans(1000);
  kick.set_hold_in_rescue(true);
  config::RescueSearch& rescue = *p.mutable_rescue();
  rescue.set_samples(16);
  rescue.set_iterations(2);
  rescue.set_full_after_narrowed(true);
  rescue.set_cost_above(1e-9);  // every re-plan in trouble: every held rescue is followed
  const PlannerTotals full = PlanThirtySteps(p);
  rescue.set_narrowed_samples(4);
  rescue.set_narrowed_iterations(1);
  const PlannerTotals small = PlanThirtySteps(p);
  constexpr int64_t kFullSearch = 16 + 15;
  constexpr int64_t kSmallSearch = 4;
  for (const PlannerTotals* t : {&full, &small}) {
    EXPECT_EQ(t->prediction_mismatches, 0);
    EXPECT_EQ(t->replans, full.replans);
    EXPECT_EQ(t->rescues, t->replans);  // one per re-plan
  }
  ASSERT_GT(full.full_after_narrowed, 0);
  ASSERT_GT(small.full_after_narrowed, 0);
  EXPECT_EQ(full.rollouts - small.rollouts,
            kFullSearch * full.full_after_narrowed - kSmallSearch * small.full_after_narrowed)
      << full.full_after_narrowed << " and " << small.full_after_narrowed << " held rescues";
}

// The same episode with and without the shared prefix: every action and rescue alike, every
// visited state as predicted, fewer rollout steps; a rescue at every re-plan covers its path.
TEST_F(SharedPrefixTest, SharingThePrefixChoosesTheSamePlansFromFewerRolloutSteps) {
  config::PlannerConfig& p = *config_.run.mutable_planner();
  ASSERT_TRUE(p.prune());
  p.mutable_rescue()->set_cost_above(1e-9);
  p.mutable_rescue()->set_samples(16);
  p.mutable_rescue()->set_iterations(2);
  std::vector<float> actions[2];
  PlannerTotals totals[2];
  for (int arm = 0; arm < 2; ++arm) {
    p.set_share_prefix(arm == 1);
    RecedingHorizonPlanner planner(std::make_shared<SoccerJuggleTask>(spec_, p), p, pool_.get(), 0);
    std::unique_ptr<JuggleEnv> env = Start();
    float action[kNumActions];
    for (int t = 0; t < 44; ++t) {  // the kick at about step 20, then its follow-through
      ASSERT_TRUE(planner.Act(*env, action).ok());
      actions[arm].insert(actions[arm].end(), action, action + kNumActions);
      ASSERT_EQ(env->Step(action, *walk_).outcome, Outcome::kRunning) << "step " << t;
    }
    totals[arm] = planner.totals();
  }
  EXPECT_EQ(actions[1], actions[0]);
  EXPECT_EQ(totals[1].rollouts, totals[0].rollouts);
  EXPECT_EQ(totals[1].rescues, totals[0].rescues);
  EXPECT_GE(totals[1].prediction_checks, 40);
  EXPECT_EQ(totals[1].prediction_mismatches, 0);
  EXPECT_LT(totals[1].rollout_steps, totals[0].rollout_steps * 0.9)
      << totals[1].rollout_steps << " against " << totals[0].rollout_steps;
}

// KickVariables.act_from_phase: no share of a set acts before that phase of the cycle, half
// of it midway to the contact, all of it from the contact on; exactly all without a ramp.
TEST_F(SharedPrefixTest, AKickRampIsZeroBeforeItsPhaseAndWholeFromTheContact) {
  SoccerPlanLayout layout = Task().layout();
  EXPECT_EQ(layout.kick_ramp(0.0), 1);
  EXPECT_EQ(layout.kick_ramp(0.3), 1);
  layout.act_from_phase = 0.25;
  EXPECT_EQ(layout.kick_ramp(0.0), 0);
  EXPECT_EQ(layout.kick_ramp(0.2499), 0);
  EXPECT_NEAR(layout.kick_ramp(0.375), 0.5, 1e-12);
  EXPECT_LT(layout.kick_ramp(0.3), layout.kick_ramp(0.45));
  EXPECT_EQ(layout.kick_ramp(0.5), 1);
  EXPECT_EQ(layout.kick_ramp(0.8), 1);
}

// With a ramp the set moves nothing before its phase (PlanActs false, two sets the same
// action), moves the swing after it, and from the contact on acts as without the ramp.
TEST_F(SharedPrefixTest, ARampedKickSetActsFromItsPhaseAndAsUnrampedAfterTheContact) {
  auto& kick = *config_.run.mutable_planner()->mutable_soccer_juggle()->mutable_kick();
  kick.set_hold_follow_through(false);
  const SoccerJuggleTask unramped = Task();
  kick.set_act_from_phase(0.25);
  const SoccerJuggleTask task = Task();
  const SoccerPlanLayout& layout = task.layout();
  ASSERT_EQ(layout.dim(), kKickVariables);
  const std::vector<double> a = {0, 0, 0, 0, 0};
  const std::vector<double> b = {0.02, 0.2, 0.1, -0.2, 0.1};
  std::unique_ptr<JuggleEnv> env = Start();
  ASSERT_LT(env->cursor().phase, 0.25);
  EXPECT_FALSE(task.PlanActs(*env, b.data(), {0, 0}));
  EXPECT_EQ(ActionOf(*env, layout, a, {0, 0}), ActionOf(*env, layout, b, {0, 0}));
  EXPECT_TRUE(unramped.PlanActs(*env, b.data(), {0, 0}));
  EXPECT_NE(ActionOf(*env, unramped.layout(), a, {0, 0}),
            ActionOf(*env, unramped.layout(), b, {0, 0}));
  // Zero action up to the ramp's middle.
  std::vector<float> zero(kNumActions, 0.0f);
  while (env->cursor().phase < 0.375) {
    ASSERT_EQ(env->Step(zero.data(), *walk_).outcome, Outcome::kRunning);
  }
  ASSERT_LT(env->cursor().phase, 0.5);
  EXPECT_TRUE(task.PlanActs(*env, b.data(), {0, 0}));
  EXPECT_NE(ActionOf(*env, layout, a, {0, 0}), ActionOf(*env, layout, b, {0, 0}));
  EXPECT_NE(ActionOf(*env, layout, b, {0, 0}), ActionOf(*env, unramped.layout(), b, {0, 0}));
  // After the kick, in the follow-through: the same actions as without the ramp.
  ASSERT_TRUE(ZeroActionKick(env.get(), *walk_).valid);
  ASSERT_GE(env->cursor().phase, 0.5);
  EXPECT_EQ(ActionOf(*env, layout, b, {0, 0}), ActionOf(*env, unramped.layout(), b, {0, 0}));
  EXPECT_NE(ActionOf(*env, layout, a, {0, 0}), ActionOf(*env, layout, b, {0, 0}));
}

// Before the contact only a ramp lets a re-plan's candidates share steps: with it, sharing
// chooses the same plans (every action, rollout and rescue alike, every state as predicted)
// from fewer rollout steps; without it sharing simulates exactly as many steps as not sharing.
TEST_F(SharedPrefixTest, ARampedKickSharesTheStepsBeforeItsPhaseAndChoosesTheSamePlans) {
  config::PlannerConfig& p = *config_.run.mutable_planner();
  p.mutable_rescue()->set_cost_above(1e-9);  // a rescue at every re-plan
  p.mutable_rescue()->set_samples(16);
  p.mutable_rescue()->set_iterations(2);
  auto run = [&](double act_from, bool share, std::vector<float>* actions) {
    p.mutable_soccer_juggle()->mutable_kick()->set_act_from_phase(act_from);
    p.set_share_prefix(share);
    RecedingHorizonPlanner planner(std::make_shared<SoccerJuggleTask>(spec_, p), p, pool_.get(), 0);
    std::unique_ptr<JuggleEnv> env = Start();
    float action[kNumActions];
    for (int t = 0; t < 12; ++t) {  // the DOWN node's first half and a bit: no release yet
      EXPECT_TRUE(planner.Act(*env, action).ok());
      actions->insert(actions->end(), action, action + kNumActions);
      EXPECT_EQ(env->Step(action, *walk_).outcome, Outcome::kRunning) << "step " << t;
      EXPECT_FALSE(env->state().kick_touched) << "step " << t;
    }
    return planner.totals();
  };
  std::vector<float> shared, simulated, unramped_shared, unramped;
  const PlannerTotals with = run(0.25, true, &shared);
  const PlannerTotals without = run(0.25, false, &simulated);
  EXPECT_EQ(shared, simulated);
  EXPECT_EQ(with.rollouts, without.rollouts);
  EXPECT_EQ(with.rescues, without.rescues);
  EXPECT_GT(with.rescues, 0);
  EXPECT_GE(with.prediction_checks, 10);
  EXPECT_EQ(with.prediction_mismatches, 0);
  EXPECT_LT(with.rollout_steps, without.rollout_steps * 0.9)
      << with.rollout_steps << " against " << without.rollout_steps;
  const PlannerTotals plain_shared = run(0, true, &unramped_shared);
  const PlannerTotals plain = run(0, false, &unramped);
  EXPECT_EQ(unramped_shared, unramped);
  EXPECT_EQ(plain_shared.rollout_steps, plain.rollout_steps);
}

}  // namespace
}  // namespace juggle::planner

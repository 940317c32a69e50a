// Football's trap then kick as a planning task (planner/football/trap_kick_task.h), found
// through the list of tasks and driven by the generic receding-horizon driver: on a pass that
// standing still does not bring into the kick's zone, the planner traps it into the zone and
// kicks it, with every visited state as predicted, and its actions replayed as plain actions
// give the same sequence bit for bit; it is deterministic for a seed across thread counts; its
// terms (the trap's, zone, out_of_reach, the kick's) add up to its cost; a ball at rest in the
// zone is 0 from it and a ball rolling away is as far as its free path's stop; the free path
// bounces as the simulated ball does, and a ball still hopping is not in the zone; a second
// touch is searched only after the touch, the trap only before it; a part's own trap settings
// set its passes' reach space.
#include "planner/football/trap_kick_task.h"

#include <cmath>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "absl/strings/str_cat.h"
#include "envs/football/env.h"
#include "envs/football/outcomes.h"
#include "envs/football/pitch.h"
#include "envs/football/trap_kick.h"
#include "envs/testing/test_configs.h"
#include "gmock/gmock.h"
#include "gtest/gtest.h"
#include "planner/football/free_ball.h"
#include "planner/planner_config.h"
#include "planner/receding_horizon.h"
#include "planner/testing/shipped_task_test.h"

namespace juggle::planner {
namespace {

using ::juggle::testing::RepoPath;

constexpr char kShippedTrapKick[] = "configs/football_trap_kick.textproto";
// A pass that standing still does not bring into the kick's zone (env seed Rng(kSeed); the
// shipped settings were chosen on juggle eval's seed 1000000, other streams). With the trap's
// settings of configs/football_trap.textproto (2026-12-06; the rescue off, SetUp) the first
// such seed after 1000039 (the one before them) that the search turns into a kick is 1000042
// (1000040 and 1000041 fail this test).
constexpr uint64_t kSeed = 1000042;

class FootballTrapKickTaskTest : public testing::ShippedTaskTest {
 protected:
  void SetUp() override {
    // The shipped config without its rescue search: a sequence with it plans from 3.7 times the
    // rollouts (docs/football.md, "Trap then kick with the trap's settings and its rescue"), and
    // what these tests check (the switch, the exact predictions, the seed's determinism) does
    // not depend on it; the rescue's space for a part is checked on its own below, the rescue's
    // search by the trap's tests (trap_task_test.cc), which run the shipped TRAP config with it.
    absl::StatusOr<LoadedConfig> c = LoadRunConfig(RepoPath(kShippedTrapKick));
    ASSERT_TRUE(c.ok()) << c.status();
    ASSERT_GT(c->run.planner().rescue().cost_above(), 0) << "the shipped config has a rescue";
    c->run.mutable_planner()->mutable_rescue()->set_cost_above(0);
    Use(*c);
    ASSERT_EQ(task_->family(), "football");
    ASSERT_EQ(task_->dim(), kTrapVariables + kKickVariables);
  }

  const football::FootballSpec& football_spec() const {
    return static_cast<const football::FootballSpec&>(*spec_);
  }

  // A reset env whose ball is still, `ahead` m in front of the right foot's standing centre and
  // `height` m above its resting height.
  std::unique_ptr<Env> EnvWithBallAhead(double ahead, double height) {
    const football::FootballSpec& spec = football_spec();
    std::unique_ptr<Env> env = spec_->NewEnv(Rng(kSeed));
    env->Reset(*walk_);
    mjData* d = env->data();
    const football::PitchBall& b = spec.ball();
    const double* foot = spec.kick_foot_standing();
    double* ball = d->qpos + b.qpos;
    ball[0] = foot[0] + ahead;
    ball[1] = foot[1];
    ball[2] = b.radius + height;
    for (int k = 0; k < 6; ++k) d->qvel[b.dof + k] = 0;
    return env;
  }
};

TEST_F(FootballTrapKickTaskTest, TrapsIntoTheZoneAndKicksWhereStandingStillDoesNotAndAsPredicted) {
  EXPECT_EQ(Run(kSeed, nullptr).Metric("trap_kick_success"), 0);
  RolloutPool pool(spec_, 2);
  RecedingHorizonPlanner planner(task_, Settings(), &pool, kSeed);
  const testing::Episode planned = Run(kSeed, &planner);
  EXPECT_EQ(planned.end, football::kKicked);
  EXPECT_EQ(planned.Metric("trap_kick_switched"), 1);
  EXPECT_EQ(planned.Metric("trap_kick_success"), 1);
  EXPECT_GT(planner.totals().prediction_checks, 10);
  EXPECT_EQ(planner.totals().prediction_mismatches, 0);
  const testing::Episode replayed = Run(kSeed, nullptr, &planned.actions);
  EXPECT_EQ(replayed.final_qpos, planned.final_qpos);
  EXPECT_EQ(replayed.end, planned.end);
}

TEST_F(FootballTrapKickTaskTest, SameSeedSameSequenceOnAnyThreadCountAnotherSeedAnother) {
  ExpectActionsDependOnlyOnTheSeed(kSeed);
}

TEST_F(FootballTrapKickTaskTest, TheTermsAddUpToTheCost) {
  std::vector<double> theta(task_->dim(), 0.0);
  theta[1] = 0.3;  // the trap's hip flexion
  const std::unique_ptr<RolloutScorer> scorer = ExpectTermsAddUpToTheCost(kSeed, theta, 200);
  EXPECT_GT(scorer->partial(), 0);
  const std::vector<std::string> names = task_->term_names();
  EXPECT_THAT(names, ::testing::Contains("zone"));
  EXPECT_THAT(names, ::testing::Contains("kick_direction"));
}

TEST_F(FootballTrapKickTaskTest, TheZoneDistanceIsZeroAtRestInTheZoneAndTheStopOfARollingBall) {
  const football::FootballSpec& spec = football_spec();
  const std::unique_ptr<Env> env = EnvWithBallAhead(0.3, 0);
  mjData* d = env->data();
  const football::PitchBall& b = spec.ball();
  const double* foot = spec.kick_foot_standing();
  double* ball = d->qpos + b.qpos;
  EXPECT_EQ(FreePathZoneDistance(*env), 0);
  // Rolling straight ahead at 1 m/s from the zone's far edge: it stops v²/2a further on.
  ball[0] = foot[0] + 0.4;
  d->qvel[b.dof] = 1.0;
  const double a = football::RollingDeceleration(spec.model(), b);
  const double limit = spec.football().trap_kick().max_speed_mps();
  // Inside the zone's far edge the ball is still faster than the limit: the least is at the
  // edge itself (0 m out, 0.5 s × the speed beyond the limit) or at the stop.
  const double at_edge = 0.5 * (1.0 - limit);
  const double at_stop = 1.0 / (2 * a);
  EXPECT_NEAR(FreePathZoneDistance(*env), std::min(at_edge, at_stop), 0.02);
}

// The free path with bounces against the simulation (the independent path): a ball dropped from
// 1.5 m with 1 m/s across, far from the character, lands and rebounds when and as high as the
// simulated one; without bounces the path rolls from the first landing.
TEST_F(FootballTrapKickTaskTest, TheFreePathBouncesAsTheSimulatedBallDoes) {
  const auto& spec = static_cast<const football::FootballSpec&>(*spec_);
  const mjModel* m = spec.model();
  mjData* d = mj_makeData(m);
  mj_resetData(m, d);
  const football::PitchBall& b = spec.ball();
  const double start[3] = {0, 20, 1.5 + b.radius};
  mju_copy3(d->qpos + b.qpos, start);
  for (int k = 0; k < 6; ++k) d->qvel[b.dof + k] = 0;
  d->qvel[b.dof] = 1.0;
  mj_forward(m, d);
  FreeBall path(spec, d, /*bounces=*/true), flat(spec, d);
  ASSERT_GT(path.bounce, 0.5);
  // Landings (the vertical speed turning upward) and the apex after the first, both ways.
  std::vector<double> sim_landings, path_landings;
  double sim_apex = 0, path_apex = 0, flat_apex = 0;
  const int per_step = static_cast<int>(std::lround(0.01 / m->opt.timestep));
  double sim_vz = 0, path_vz = 0;
  for (double t = 0.01; t < 1.8; t += 0.01) {
    for (int i = 0; i < per_step; ++i) mj_step(m, d);
    path.Step(0.01);
    flat.Step(0.01);
    const double vz = d->qvel[b.dof + 2], z = d->qpos[b.qpos + 2];
    if (sim_vz < 0 && vz > 0) sim_landings.push_back(t);
    if (path_vz < 0 && path.v[2] > 0) path_landings.push_back(t);
    sim_vz = vz;
    path_vz = path.v[2];
    if (sim_landings.size() == 1) sim_apex = std::max(sim_apex, z - b.radius);
    if (path_landings.size() == 1) path_apex = std::max(path_apex, path.p[2] - b.radius);
    if (t > 0.6) flat_apex = std::max(flat_apex, flat.p[2] - b.radius);
  }
  mj_deleteData(d);
  ASSERT_GE(sim_landings.size(), 2u);
  ASSERT_GE(path_landings.size(), 2u);
  for (int k = 0; k < 2; ++k) EXPECT_NEAR(path_landings[k], sim_landings[k], 0.03) << "landing " << k;
  EXPECT_NEAR(path_apex, sim_apex, 0.03);
  EXPECT_GT(sim_apex, 0.4) << "a 1.5-m drop rebounds about 0.58 m";
  EXPECT_EQ(flat_apex, 0) << "without bounces the path rolls from the first landing";
}

TEST_F(FootballTrapKickTaskTest, ABallStillHoppingAtTheEndOfItsPathIsNotInTheZone) {
  // Dropped onto the zone from 1 m: it settles within the path's 3 s.
  EXPECT_EQ(FreePathZoneDistance(*EnvWithBallAhead(0.3, 1.0)), 0);
  // From 4 m it still hops 3 s later (its sixth rebound, of e ≈ 0.62, rises 1.3 cm at 3.6 s).
  EXPECT_GT(FreePathZoneDistance(*EnvWithBallAhead(0.3, 4.0)), 0.01);
}

// With planner.football.second_touch the plan has the second touch's variables between the
// trap's and the kick's; every visited state is as predicted and its actions replay bit for bit.
TEST_F(FootballTrapKickTaskTest, ASecondTouchIsPlannedBetweenTrapAndKickAndAsPredicted) {
  const std::string text = absl::StrCat("base_config: \"", RepoPath(kShippedTrapKick),
                                        "\"\nplanner { football { second_touch { enabled: true } } "
                                        "rescue { cost_above: 0 } }\n");  // as SetUp
  Use(LoadRunConfig(::juggle::testing::WriteTemp("football_second_touch.textproto", text)));
  ASSERT_EQ(task_->dim(), kTrapVariables + kSecondTouchVariables + kKickVariables);
  RolloutPool pool(spec_, 2);
  RecedingHorizonPlanner planner(task_, Settings(), &pool, kSeed);
  const testing::Episode planned = Run(kSeed, &planner);
  EXPECT_GT(planner.totals().prediction_checks, 10);
  EXPECT_EQ(planner.totals().prediction_mismatches, 0);
  const testing::Episode replayed = Run(kSeed, nullptr, &planned.actions);
  EXPECT_EQ(replayed.final_qpos, planned.final_qpos);
  EXPECT_EQ(replayed.end, planned.end);
}

// The second touch is a decision of its own: before the designated part's touch it acts
// nothing and the search holds it (the trap's reach is searched); from the touch on the search
// holds the trap's reach and moves the second touch.
TEST_F(FootballTrapKickTaskTest, ASecondTouchIsSearchedOnlyAfterTheTouchAndTheTrapOnlyBefore) {
  const std::string text = absl::StrCat("base_config: \"", RepoPath(kShippedTrapKick),
                                        "\"\nplanner { football { second_touch { enabled: true } } "
                                        "rescue { cost_above: 0 } }\n");  // as SetUp
  Use(LoadRunConfig(::juggle::testing::WriteTemp("football_second_touch_own.textproto", text)));
  const int second = kTrapVariables, kick = kTrapVariables + kSecondTouchVariables;
  std::unique_ptr<Env> env = spec_->NewEnv(Rng(kSeed));
  env->Reset(*walk_);
  const std::vector<double> shifted(task_->dim(), 0.0);
  // A plan whose second touch would bend the leg hard at once, and the same without it.
  std::vector<double> with(task_->dim(), 0.0), without(task_->dim(), 0.0);
  with[second] = 0.1;
  for (int v = second + 1; v < kick - 1; ++v) with[v] = 0.8;
  std::vector<float> a(spec_->act_dim()), b(spec_->act_dim());
  const auto& trap = static_cast<const football::FootballEnv&>(*env).state().trap;
  const std::vector<float> zero(spec_->act_dim(), 0.0f);
  int touched_at = -1;
  for (int t = 0; t < 100 && touched_at < 0; ++t) {
    SearchSpace space = task_->space();
    std::vector<std::vector<double>> seeds = {std::vector<double>(task_->dim(), 0.3)};
    task_->Restrict(*env, shifted, &space, &seeds);
    task_->Action(*env, with.data(), PlanClock{}, nullptr, a.data());
    task_->Action(*env, without.data(), PlanClock{}, nullptr, b.data());
    if (trap.first_touch_s < 0) {
      EXPECT_EQ(a, b) << "the second touch acts before the touch at step " << t;
      EXPECT_GT(space.sigma[0], 0) << "the trap's reach is searched before the touch";
      for (int v = second; v < kick; ++v) {
        EXPECT_EQ(space.sigma[v], 0) << v;
        EXPECT_EQ(seeds[0][v], 0) << v;
      }
    } else {
      touched_at = t;
      for (int v = 0; v < second; ++v) {
        EXPECT_EQ(space.sigma[v], 0) << v;
        EXPECT_EQ(seeds[0][v], 0) << v;
      }
      EXPECT_GT(space.sigma[second + 1], 0) << "the second touch is searched after the touch";
      EXPECT_EQ(seeds[0][second + 1], 0.3);
    }
    env->Step(zero.data(), *walk_);
  }
  ASSERT_GE(touched_at, 0) << "standing still, the pass should touch the character";
  // A step later the leg is on its way (the reach's smoothstep begins at once for a reach due
  // 0.1 s after the touch).
  task_->Action(*env, with.data(), PlanClock{}, nullptr, a.data());
  task_->Action(*env, without.data(), PlanClock{}, nullptr, b.data());
  EXPECT_NE(a, b) << "the second touch acts after the touch";
}

// trap.foot (a part's own trap settings, trap_task.h's TrapPlanningFor) reaches the trap inside
// trap then kick: a foot pass's reach angles are searched at the foot's spread in the regular
// and the rescue search, a chest pass's at the trap's, and the kick's variables at the kick's.
TEST_F(FootballTrapKickTaskTest, APartsOwnTrapSettingsSetItsPassesReachSpaceOnly) {
  absl::StatusOr<LoadedConfig> loaded = LoadRunConfig(RepoPath(kShippedTrapKick));
  ASSERT_TRUE(loaded.ok()) << loaded.status();
  LoadedConfig c = *loaded;
  const config::TrapPlanning& base = c.run.planner().football().trap();
  const double foot_sigma = 3 * base.angle_sigma();
  c.run.mutable_planner()->mutable_football()->mutable_trap()->mutable_foot()->set_angle_sigma(
      foot_sigma);
  ASSERT_TRUE(ValidatePlannerConfig(c).ok()) << ValidatePlannerConfig(c);
  Use(c);
  const auto part_of = [&](uint64_t seed) {
    const std::unique_ptr<Env> env = spec_->NewEnv(Rng(seed));
    env->Reset(*walk_);
    const football::TrapEpisode& t = static_cast<const football::FootballEnv&>(*env).state().trap;
    return t.pass.kind == football::PassKind::kGround ? config::TRAP_PART_UNSPECIFIED : t.part;
  };
  int checked = 0;
  for (config::TrapPart part : {config::FOOT, config::TORSO}) {
    uint64_t seed = kSeed;
    while (part_of(seed) != part) ++seed;
    const std::unique_ptr<Env> env = spec_->NewEnv(Rng(seed));
    env->Reset(*walk_);
    const std::vector<double> shifted(task_->dim(), 0.0);
    std::vector<std::vector<double>> seeds = {shifted};
    SearchSpace space = task_->space();
    task_->Restrict(*env, shifted, &space, &seeds);
    const double want = part == config::FOOT ? foot_sigma : base.angle_sigma();
    const std::pair<SearchSpace, const SearchSpace*> searches[] = {
        {space, &task_->space()}, {task_->RescueSpaceAt(*env), &task_->rescue_space()}};
    for (const auto& [s, unrestricted] : searches) {
      for (int v = 1; v < kTrapVariables - 1; ++v) EXPECT_EQ(s.sigma[v], want) << seed << " " << v;
      EXPECT_EQ(s.sigma[0], base.timing_sigma_s()) << seed;
      for (int v = kTrapVariables; v < task_->dim(); ++v) {
        EXPECT_EQ(s.sigma[v], unrestricted->sigma[v]) << seed << " " << v;
      }
    }
    ++checked;
  }
  EXPECT_EQ(checked, 2);
}

TEST_F(FootballTrapKickTaskTest, ASecondTouchOutsideTrapThenKickOrOutOfOrderIsRefusedAtTheField) {
  using ::juggle::testing::Loc;
  using ::juggle::testing::WriteTemp;
  const std::string on_trap = absl::StrCat(
      "base_config: \"", RepoPath("configs/football_trap.textproto"),
      "\"\nplanner {\n  football { second_touch { enabled: true } }\n}\n");
  const std::string path = WriteTemp("football_trap_second_touch.textproto", on_trap);
  absl::StatusOr<LoadedConfig> c = LoadRunConfig(path);
  ASSERT_TRUE(c.ok()) << c.status();
  absl::Status s = ValidatePlannerConfig(*c);
  EXPECT_EQ(s.code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(std::string(s.message()), ::testing::StartsWith(Loc(path, on_trap, "enabled")));
  EXPECT_THAT(std::string(s.message()), ::testing::HasSubstr("TRAP_KICK"));

  const std::string reversed = absl::StrCat("base_config: \"", RepoPath(kShippedTrapKick),
                                            "\"\nplanner {\n  football { second_touch { enabled: "
                                            "true earliest_s: 1.0 latest_s: 0.5 } }\n}\n");
  const std::string path2 = WriteTemp("football_second_touch_reversed.textproto", reversed);
  c = LoadRunConfig(path2);
  ASSERT_TRUE(c.ok()) << c.status();
  s = ValidatePlannerConfig(*c);
  EXPECT_EQ(s.code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(std::string(s.message()), ::testing::StartsWith(Loc(path2, reversed, "earliest_s")));
}

}  // namespace
}  // namespace juggle::planner

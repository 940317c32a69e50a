// The football family's TRAP_KICK env (envs/football/env.h, trap_kick.h): a slow ball that the
// designated foot touches and that rolls off into the kick's zone switches the env to the kick,
// whose clock starts there and whose touch and window are the kick's; a ball the trap sends out
// of the zone ends the episode as out_of_reach wait_s after the touch; the zone's distance in
// the ground plane; the sequence's metrics and the summary's trap_kick=; a zone out of order is
// refused naming file, line and field.
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "absl/strings/str_cat.h"
#include "envs/football/env.h"
#include "envs/football/outcomes.h"
#include "envs/football/trap_kick.h"
#include "envs/registry.h"
#include "envs/testing/test_configs.h"
#include "gmock/gmock.h"
#include "gtest/gtest.h"

namespace juggle::football {
namespace {

using ::juggle::testing::Loc;
using ::juggle::testing::RepoPath;
using ::juggle::testing::WriteTemp;
using ::testing::HasSubstr;
using ::testing::StartsWith;

constexpr char kShippedTrapKick[] = "configs/football_trap_kick.textproto";

class FootballTrapKickEnvTest : public ::testing::Test {
 protected:
  // Ground passes to the foot only: the tests set the ball themselves.
  void SetUp() override { UseFootball("trap { lob_fraction: 0 }"); }

  // The shipped config with `fields` added inside `football { ... }`.
  void UseFootball(const std::string& fields) {
    path_ = WriteTemp("football_trap_kick_variant.textproto",
                      absl::StrCat("base_config: \"", RepoPath(kShippedTrapKick),
                                   "\"\nfootball {\n  ", fields, "\n}\n"));
    absl::StatusOr<LoadedConfig> config = LoadRunConfig(path_);
    ASSERT_TRUE(config.ok()) << config.status();
    absl::StatusOr<std::shared_ptr<const EnvSpec>> spec = CreateEnvSpec(*config);
    ASSERT_TRUE(spec.ok()) << spec.status();
    spec_ = std::static_pointer_cast<const FootballSpec>(*spec);
    walk_ = std::make_unique<AdaptiveWalk>(&spec_->graph());
  }

  std::unique_ptr<FootballEnv> NewEnv(uint64_t seed) {
    std::unique_ptr<Env> env = spec_->NewEnv(Rng(seed));
    env->Reset(*walk_);
    return std::unique_ptr<FootballEnv>(static_cast<FootballEnv*>(env.release()));
  }

  // Puts the ball on the turf `ahead` m in front of the right foot's centre (its toe touches a
  // ball about 0.2 m ahead), rolling back toward it at `speed` m/s without slipping.
  void RollIntoTheToe(FootballEnv* env, double speed, double ahead = 0.35) const {
    mjData* d = env->data();
    const PitchBall& b = spec_->ball();
    const double* foot = spec_->kick_foot_standing();
    double* ball = d->qpos + b.qpos;
    ball[0] = foot[0] + ahead;
    ball[1] = foot[1];
    ball[2] = b.radius;
    double* v = d->qvel + b.dof;
    for (int k = 0; k < 6; ++k) v[k] = 0;
    v[0] = -speed;
    v[4] = v[0] / b.radius;
    mj_forward(spec_->model(), d);
  }

  static double Metric(const FootballEnv& env, const std::string& name) {
    std::vector<NamedValue> metrics;
    env.AppendEpisodeMetrics(&metrics);
    for (const NamedValue& m : metrics) {
      if (m.name == name) return m.value;
    }
    return NAN;
  }

  std::string path_;
  std::shared_ptr<const FootballSpec> spec_;
  std::unique_ptr<AdaptiveWalk> walk_;
};

TEST_F(FootballTrapKickEnvTest, ASlowBallOffTheFootIntoTheZoneSwitchesToTheKickOnItsOwnClock) {
  const std::unique_ptr<FootballEnv> env = NewEnv(5);
  ASSERT_EQ(env->state().trap.part, config::FOOT);
  ASSERT_FALSE(env->kicking());
  EXPECT_TRUE(std::isnan(Metric(*env, "trap_kick_switch_s")));
  RollIntoTheToe(env.get(), 1.0);
  const std::vector<float> zero(kNumActions, 0.0f);
  Outcome end = Outcome::kRunning;
  double switched_at = -1;
  for (int i = 0; i < 300 && end == Outcome::kRunning; ++i) {
    end = env->Step(zero.data(), *walk_).outcome;
    if (switched_at < 0 && env->kicking()) {
      switched_at = env->time_s();
      // The switch: after the foot's touch, the ball in the zone and slow, the kick's clock at 0.
      EXPECT_EQ(env->state().trap.first_body, spec_->trap_bodies().body[config::FOOT]);
      EXPECT_GT(switched_at, env->state().trap.first_touch_s);
      EXPECT_TRUE(BallKickable(*spec_, env->data()));
      EXPECT_DOUBLE_EQ(env->kick_time_s(), 0);
      EXPECT_EQ(env->state().touch_body, -1) << "the kick's touches count from the switch";
      // A ball still against the foot arms the kick's touch only once it is free.
      EXPECT_EQ(env->state().touch_armed, !BallTouchesCharacter(*spec_, env->data()));
      EXPECT_TRUE(env->state().trap.settled) << "the trap ends at the switch";
    }
  }
  ASSERT_GT(switched_at, 0) << "never switched; ended as " << static_cast<int>(end);
  EXPECT_EQ(Metric(*env, "trap_kick_switched"), 1);
  EXPECT_DOUBLE_EQ(Metric(*env, "trap_kick_switch_s"), switched_at);
  EXPECT_EQ(Metric(*env, "trap_success"), 1);
  // The scripted kick then touches the ball with the right foot, after the switch.
  EXPECT_EQ(end, kKicked);
  EXPECT_GT(Metric(*env, "kick_touch_s"), switched_at);
  EXPECT_EQ(Metric(*env, "trap_kick_success"), Metric(*env, "kick_success"));
  EXPECT_EQ(env->completions(), static_cast<int>(Metric(*env, "kick_success")));
}

TEST_F(FootballTrapKickEnvTest, ABallSentOutOfTheZoneEndsAsOutOfReachWaitSecondsAfterTheTouch) {
  UseFootball("trap { lob_fraction: 0 } trap_kick { wait_s: 0.6 }");
  const std::unique_ptr<FootballEnv> env = NewEnv(5);
  RollIntoTheToe(env.get(), 4.0);  // bounces off the toe and rolls away fast
  const std::vector<float> zero(kNumActions, 0.0f);
  Outcome end = Outcome::kRunning;
  for (int i = 0; i < 300 && end == Outcome::kRunning; ++i) {
    end = env->Step(zero.data(), *walk_).outcome;
  }
  EXPECT_EQ(end, kOutOfReach);
  EXPECT_FALSE(env->kicking());
  const double touch = env->state().trap.first_touch_s;
  ASSERT_GE(touch, 0);
  EXPECT_GE(env->data()->time - touch, 0.6 - 1e-9);
  EXPECT_LT(env->data()->time - touch, 0.6 + spec_->control_dt());
  EXPECT_EQ(Metric(*env, "trap_kick_switched"), 0);
  EXPECT_EQ(Metric(*env, "trap_kick_success"), 0);
  EXPECT_TRUE(std::isnan(Metric(*env, "kick_success"))) << "no kick was attempted";
  EXPECT_EQ(env->completions(), 0);
  // Where the unkicked ball ended, against the foot's standing centre, read off the physics.
  const PitchBall& b = spec_->ball();
  const double* p = env->data()->qpos + b.qpos;
  const double* v = env->data()->qvel + b.dof;
  const double* foot = spec_->kick_foot_standing();
  EXPECT_DOUBLE_EQ(Metric(*env, "trap_kick_ball_ahead_m"), p[0] - foot[0]);
  EXPECT_DOUBLE_EQ(Metric(*env, "trap_kick_ball_across_m"), p[1] - foot[1]);
  EXPECT_DOUBLE_EQ(Metric(*env, "trap_kick_ball_speed_mps"), std::hypot(v[0], v[1]));
  EXPECT_GT(Metric(*env, "trap_kick_ball_ahead_m"), 0.40) << "sent away ahead, out of the zone";
  EXPECT_GT(Metric(*env, "trap_kick_zone_distance_m"), 0);
  EXPECT_NEAR(Metric(*env, "trap_kick_ball_height_m"), p[2] - b.radius, 1e-12);
}

TEST_F(FootballTrapKickEnvTest, TheZoneDistanceIsZeroInsideAndTheGapOutside) {
  const double* foot = spec_->kick_foot_standing();
  // Defaults: 0.15-0.40 m ahead, 0.12 m across.
  EXPECT_EQ(KickZoneDistance(*spec_, foot[0] + 0.3, foot[1] + 0.1), 0);
  EXPECT_NEAR(KickZoneDistance(*spec_, foot[0] + 0.5, foot[1]), 0.1, 1e-12);
  EXPECT_NEAR(KickZoneDistance(*spec_, foot[0] + 0.1, foot[1]), 0.05, 1e-12);
  EXPECT_NEAR(KickZoneDistance(*spec_, foot[0] + 0.43, foot[1] - 0.16), 0.05, 1e-12);
}

TEST_F(FootballTrapKickEnvTest, TheSummaryLineCountsSequencesThatSucceeded) {
  const std::vector<std::vector<NamedValue>> episodes = {
      {{"trap_kick_success", 1}}, {{"trap_kick_success", 0}}, {{"trap_kick_success", 1}},
      {{"trap_kick_success", 1}}};
  EXPECT_THAT(spec_->EvaluationLine(episodes), HasSubstr("trap_kick=0.750"));
}

TEST_F(FootballTrapKickEnvTest, AZoneOutOfOrderIsRefusedNamingFileLineAndField) {
  const std::string text = absl::StrCat(
      "base_config: \"", RepoPath(kShippedTrapKick),
      "\"\nfootball {\n  trap_kick { zone_ahead_min_m: 0.5 zone_ahead_max_m: 0.3 }\n}\n");
  const std::string path = WriteTemp("football_trap_kick_bad_zone.textproto", text);
  absl::StatusOr<LoadedConfig> config = LoadRunConfig(path);
  ASSERT_FALSE(config.ok());
  EXPECT_THAT(std::string(config.status().message()),
              StartsWith(Loc(path, text, "zone_ahead_min_m")));
  EXPECT_THAT(std::string(config.status().message()), HasSubstr("trap_kick.zone_ahead_min_m"));
}

}  // namespace
}  // namespace juggle::football

// The football family's KICK env (envs/football/env.h) and its config (family.cc): the shipped
// config makes an env of the documented sizes; a reset draws the ball and the target inside
// their ranges, deterministically per seed; snapshots restore bit for bit through a kick and
// refuse another family's; the episode's kick metrics equal the metrics recomputed by hand from
// the ball velocities seen after each step; config errors name file, line and field.
#include "envs/football/env.h"

#include <cmath>
#include <memory>
#include <string>
#include <tuple>
#include <vector>

#include "absl/strings/str_cat.h"
#include "envs/football/outcomes.h"
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

constexpr char kShipped[] = "configs/football_kick.textproto";

class FootballEnvTest : public ::testing::Test {
 protected:
  void SetUp() override { Use(LoadRunConfig(RepoPath(kShipped))); }

  void Use(absl::StatusOr<LoadedConfig> config) {
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

  // The released scripted kick (hip to 0.9 rad, the knee to 0.1, no whip): with zero action it
  // kicks and stands, where the shipped faster script falls after its touch without the
  // planner's corrections (docs/football.md, "A faster kick").
  void UseReleasedScript() {
    Use(LoadRunConfig(
        WriteTemp("football_released_kick.textproto",
                  absl::StrCat("base_config: \"", RepoPath(kShipped),
                               "\"\nname: \"released\"\nfootball { motion { hip_forward: 0.9 "
                               "knee_forward: 0.1 knee_back: 1.2 knee_lag: 0 } }\n"))));
  }

  // A deterministic, varied action for step `step`.
  static std::vector<float> ActionAt(int step) {
    std::vector<float> a(kNumActions);
    for (int i = 0; i < kNumActions; ++i) a[i] = 0.05f * std::sin(0.7f * step + 1.3f * i);
    return a;
  }

  std::shared_ptr<const FootballSpec> spec_;
  std::unique_ptr<AdaptiveWalk> walk_;
};

TEST_F(FootballEnvTest, TheShippedKickConfigMakesAnEnvOfTheDocumentedSizes) {
  EXPECT_EQ(spec_->family(), "football");
  EXPECT_EQ(spec_->obs_dim(), kObservationSize);
  EXPECT_EQ(spec_->obs_dim(), 89);
  EXPECT_EQ(spec_->act_dim(), 28);
  EXPECT_DOUBLE_EQ(spec_->control_dt(), 0.02);
  EXPECT_THAT(spec_->outcome_names(), ::testing::Contains("kicked"));
  EXPECT_EQ(spec_->graph().num_nodes(), 0);
}

TEST_F(FootballEnvTest, AResetDrawsTheBallAndTheTargetInsideTheirRangesAndRepeatsPerSeed) {
  const config::KickTargets& k = spec_->football().kick();
  const double* foot = spec_->kick_foot_standing();
  for (uint64_t seed = 0; seed < 40; ++seed) {
    SCOPED_TRACE(seed);
    std::unique_ptr<FootballEnv> env = NewEnv(seed);
    const double* ball = env->data()->qpos + spec_->ball().qpos;
    const double* v = env->data()->qvel + spec_->ball().dof;
    EXPECT_NEAR(ball[0], foot[0] + k.ball_ahead_m(), k.position_jitter_m() + 1e-12);
    EXPECT_NEAR(ball[1], foot[1] + k.ball_side_m(), k.position_jitter_m() + 1e-12);
    EXPECT_DOUBLE_EQ(ball[2], spec_->ball().radius);
    EXPECT_LE(std::hypot(v[0], v[1]), k.ball_speed_max_mps());
    // Away or across, never into the standing foot.
    if (std::hypot(v[0], v[1]) > 0) {
      EXPECT_LE(std::abs(std::atan2(v[1], v[0])) * 180 / M_PI, k.roll_heading_max_deg() + 1e-9);
    }
    // Rolling without slipping: the contact point is at rest.
    EXPECT_NEAR(v[0] - v[4] * spec_->ball().radius, 0, 1e-12);
    EXPECT_NEAR(v[1] + v[3] * spec_->ball().radius, 0, 1e-12);
    const KickAttempt& target = env->state().kick;
    EXPECT_GE(target.target_speed, k.speed_min_mps());
    EXPECT_LE(target.target_speed, k.speed_max_mps());
    const double* d = target.target_direction;
    EXPECT_NEAR(std::hypot(d[0], d[1], d[2]), 1, 1e-12);
    const double elevation = std::asin(d[2]) * 180 / M_PI;
    EXPECT_GE(elevation, k.elevation_min_deg() - 1e-9);
    EXPECT_LE(elevation, k.elevation_max_deg() + 1e-9);
    EXPECT_LE(std::abs(std::atan2(d[1], d[0]) * 180 / M_PI), k.azimuth_max_deg() + 1e-9);
    // The character stands clear of the ball.
    EXPECT_EQ(env->state().touch_body, -1);
    std::unique_ptr<FootballEnv> again = NewEnv(seed);
    EXPECT_EQ(again->state().kick.target_speed, target.target_speed);
    EXPECT_EQ(again->data()->qpos[spec_->ball().qpos + 1], ball[1]);
  }
  EXPECT_NE(NewEnv(1)->state().kick.target_speed, NewEnv(2)->state().kick.target_speed);
}

TEST_F(FootballEnvTest, ASnapshotRestoredStepsBitForBitThroughTheKick) {
  std::unique_ptr<FootballEnv> original = NewEnv(5);
  for (int step = 0; step < 10; ++step) original->Step(ActionAt(step).data(), *walk_);
  std::unique_ptr<EnvSnapshot> snapshot = original->Snapshot();
  std::unique_ptr<FootballEnv> copy = NewEnv(6);  // another start, replaced by the restore
  ASSERT_TRUE(copy->Restore(*snapshot).ok());
  const int nq = spec_->model()->nq, nv = spec_->model()->nv;
  bool touched = false;
  for (int step = 10; step < 60; ++step) {
    const StepResult a = original->Step(ActionAt(step).data(), *walk_);
    const StepResult b = copy->Step(ActionAt(step).data(), *walk_);
    ASSERT_EQ(a.outcome, b.outcome);
    for (int i = 0; i < nq; ++i) ASSERT_EQ(original->data()->qpos[i], copy->data()->qpos[i]);
    for (int i = 0; i < nv; ++i) ASSERT_EQ(original->data()->qvel[i], copy->data()->qvel[i]);
    ASSERT_EQ(original->state().touch_time_s, copy->state().touch_time_s);
    ASSERT_EQ(original->state().kick.after_touch.size(), copy->state().kick.after_touch.size());
    touched = touched || original->state().touch_body >= 0;
    if (a.outcome != Outcome::kRunning) break;
  }
  EXPECT_TRUE(touched) << "the scripted kick should touch the ball within 1 s";
}

TEST_F(FootballEnvTest, ASnapshotOfAnotherFamilyIsRefused) {
  absl::StatusOr<LoadedConfig> juggling = LoadRunConfig(RepoPath("configs/right_foot_planner.textproto"));
  ASSERT_TRUE(juggling.ok()) << juggling.status();
  absl::StatusOr<std::shared_ptr<const EnvSpec>> spec = CreateEnvSpec(*juggling);
  ASSERT_TRUE(spec.ok()) << spec.status();
  std::unique_ptr<Env> soccer = (*spec)->NewEnv(Rng(1));
  AdaptiveWalk soccer_walk(&(*spec)->graph());
  soccer->Reset(soccer_walk);
  const absl::Status status = NewEnv(1)->Restore(*soccer->Snapshot());
  EXPECT_EQ(status.code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(status.message(), HasSubstr("soccer_juggle"));
}

TEST_F(FootballEnvTest, TheKickMetricsAreThoseRecomputedFromTheBallVelocityAfterEachStep) {
  UseReleasedScript();
  int kicks = 0;
  for (uint64_t seed = 0; seed < 6; ++seed) {
    SCOPED_TRACE(seed);
    std::unique_ptr<FootballEnv> env = NewEnv(seed);
    const std::vector<float> zero(kNumActions, 0.0f);
    double target[3];
    env->TargetVelocity(target);
    const double target_speed = std::hypot(target[0], target[1], target[2]);
    double angles = 0, speeds = 0, signed_speeds = 0;
    int samples = 0;
    StepResult r;
    while (r.outcome == Outcome::kRunning) {
      r = env->Step(zero.data(), *walk_);
      const FootballEnvState& s = env->state();
      if (!s.kick.touched) continue;
      const double since = env->data()->time - s.touch_time_s;
      if (since > kKickWindowS + 1e-9) continue;
      // By hand: acos of the normalized dot product (metrics.cc uses atan2 of |a × b| and a·b).
      const double* v = env->data()->qvel + spec_->ball().dof;
      const double speed = std::hypot(v[0], v[1], v[2]);
      const double dot = (v[0] * target[0] + v[1] * target[1] + v[2] * target[2]) /
                         (speed * target_speed);
      angles += std::acos(std::clamp(dot, -1.0, 1.0)) * 180 / M_PI;
      speeds += std::abs(speed - target_speed);
      signed_speeds += speed - target_speed;
      ++samples;
    }
    std::vector<NamedValue> metrics;
    env->AppendEpisodeMetrics(&metrics);
    auto value = [&](const std::string& name) {
      for (const NamedValue& m : metrics) {
        if (m.name == name) return m.value;
      }
      return std::nan("");
    };
    if (samples == 0) {
      EXPECT_EQ(value("kick_success"), 0);
      continue;
    }
    ++kicks;
    EXPECT_EQ(value("kick_success"), 1);
    EXPECT_NEAR(value("kick_direction_deviation_deg"), angles / samples, 1e-6);
    EXPECT_NEAR(value("kick_speed_deviation_mps"), speeds / samples, 1e-9);
    EXPECT_NEAR(value("kick_target_speed_mps"), target_speed, 1e-9);
    EXPECT_NEAR(value("kick_speed_error_mps"), signed_speeds / samples, 1e-9);
    EXPECT_LE(std::abs(value("kick_elevation_error_deg")), value("kick_direction_deviation_deg"));
    EXPECT_LE(value("kick_direction_floor_deg"), value("kick_direction_deviation_deg"));
    EXPECT_LE(value("kick_speed_floor_mps"), value("kick_speed_deviation_mps") + 1e-12);
  }
  EXPECT_GT(kicks, 0) << "the scripted kick touched no ball with zero action";
}

TEST_F(FootballEnvTest, TheFirstTouchNamesThePartOfTheCharacterThatMadeIt) {
  UseReleasedScript();
  const std::vector<float> zero(kNumActions, 0.0f);
  // The three first-touch metrics as a string, "kicking_leg standing_leg upper_body".
  auto touch_part = [&](FootballEnv& env, Outcome* outcome) {
    StepResult r;
    while (r.outcome == Outcome::kRunning) r = env.Step(zero.data(), *walk_);
    *outcome = r.outcome;
    std::vector<NamedValue> metrics;
    env.AppendEpisodeMetrics(&metrics);
    std::string parts;
    for (const char* name :
         {"kick_touch_kicking_leg", "kick_touch_standing_leg", "kick_touch_upper_body"}) {
      std::string value = "-";
      for (const NamedValue& m : metrics) {
        if (m.name == name) value = absl::StrCat(m.value);
      }
      absl::StrAppend(&parts, parts.empty() ? "" : " ", value);
    }
    return parts;
  };
  // The scripted kick with zero action: the kicking foot first.
  std::unique_ptr<FootballEnv> kick = NewEnv(0);
  Outcome outcome;
  EXPECT_EQ(touch_part(*kick, &outcome), "0 0 0");
  EXPECT_EQ(outcome, kKicked);
  // The ball dropped at rest onto a body (the head, the standing boot's toe ahead of its shin,
  // the kicking shin): that body's part first, a wrong touch.
  const mjModel* m = spec_->model();
  // (body, metres ahead of its origin, metres above it, the metrics expected)
  for (const auto& [body, ahead, above, part] :
       std::vector<std::tuple<const char*, double, double, std::string>>{
           {"neck", 0, 0.4, "0 0 1"},
           {"left_ankle", 0.18, 0.2, "0 1 0"},
           {"right_ankle", 0.15, 0.2, "1 0 0"}}) {
    SCOPED_TRACE(body);
    std::unique_ptr<FootballEnv> env = NewEnv(0);
    mjData* d = env->data();
    const double* at = d->xpos + 3 * mj_name2id(m, mjOBJ_BODY, body);
    double* ball = d->qpos + spec_->ball().qpos;
    ball[0] = at[0] + ahead;
    ball[1] = at[1];
    ball[2] = at[2] + above;
    for (int i = 0; i < 6; ++i) d->qvel[spec_->ball().dof + i] = 0;
    EXPECT_EQ(touch_part(*env, &outcome), part);
    EXPECT_EQ(outcome, kWrongTouch);
  }
}

TEST(FootballConfigTest, ConfigErrorsNameFileLineAndField) {
  const std::string no_task = "name: \"x\"\nfootball {\n  settle_s: 0.5\n}\n";
  absl::StatusOr<LoadedConfig> c = LoadRunConfig(WriteTemp("football_no_task.textproto", no_task));
  ASSERT_FALSE(c.ok());
  EXPECT_THAT(c.status().message(), HasSubstr("football_no_task.textproto"));
  EXPECT_THAT(c.status().message(), HasSubstr("task"));
  EXPECT_THAT(c.status().message(), HasSubstr("KICK"));

  const std::string speeds =
      "name: \"x\"\nfootball {\n  task: KICK\n  kick { speed_min_mps: 20 speed_max_mps: 10 }\n}\n";
  c = LoadRunConfig(WriteTemp("football_speeds.textproto", speeds));
  ASSERT_FALSE(c.ok());
  EXPECT_THAT(std::string(c.status().message()),
              StartsWith(Loc(WriteTemp("football_speeds.textproto", speeds), speeds, "speed_min_mps")));
  EXPECT_THAT(c.status().message(), HasSubstr("speed_max_mps"));

  const std::string short_episode =
      "name: \"x\"\nfootball {\n  task: KICK\n  max_episode_steps: 20\n}\n";
  c = LoadRunConfig(WriteTemp("football_short.textproto", short_episode));
  ASSERT_FALSE(c.ok());
  EXPECT_THAT(std::string(c.status().message()),
              StartsWith(Loc(WriteTemp("football_short.textproto", short_episode), short_episode,
                             "max_episode_steps")));
  EXPECT_THAT(c.status().message(), HasSubstr("settle_s"));

  const std::string bad_joint = absl::StrCat(
      "name: \"x\"\nfootball {\n  task: KICK\n  model_file: \"",
      RepoPath("configs/models/football_pitch.xml"),
      "\"\n  rest_pose { joint: \"tail\" value: 1 }\n}\n");
  c = LoadRunConfig(WriteTemp("football_joint.textproto", bad_joint));
  ASSERT_TRUE(c.ok()) << c.status();
  absl::StatusOr<std::shared_ptr<const EnvSpec>> spec = CreateEnvSpec(*c);
  ASSERT_FALSE(spec.ok());
  EXPECT_THAT(spec.status().message(), HasSubstr("unknown joint 'tail'"));
  EXPECT_THAT(std::string(spec.status().message()),
              StartsWith(Loc(WriteTemp("football_joint.textproto", bad_joint), bad_joint, "joint:")));
}

}  // namespace
}  // namespace juggle::football

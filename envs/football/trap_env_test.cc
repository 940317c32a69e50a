// The football family's TRAP env (envs/football/env.h, trap_episode.h): a drawn lob flies as the
// analytic flight that comes down through its meeting point (within the integrator's error) in
// front of the designated part; ground passes go to the foot; snapshots restore bit for bit
// through a touch; a ball dropped on the head is a touch by the head, a trap when the head is
// the designated part and a wrong part otherwise, with the relative speed's frames recorded; a
// lob on the turf first is ground_first; config errors (lobs too weak for the part, ranges out
// of order, a part the model lacks) name file, line and field.
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "absl/strings/str_cat.h"
#include "envs/football/env.h"
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

constexpr char kShippedTrap[] = "configs/football_trap.textproto";

class FootballTrapEnvTest : public ::testing::Test {
 protected:
  void SetUp() override { Use(RepoPath(kShippedTrap)); }

  void Use(const std::string& path) {
    absl::StatusOr<LoadedConfig> config = LoadRunConfig(path);
    ASSERT_TRUE(config.ok()) << config.status();
    absl::StatusOr<std::shared_ptr<const EnvSpec>> spec = CreateEnvSpec(*config);
    ASSERT_TRUE(spec.ok()) << spec.status();
    spec_ = std::static_pointer_cast<const FootballSpec>(*spec);
    walk_ = std::make_unique<AdaptiveWalk>(&spec_->graph());
  }

  // The shipped config with `football_fields` added inside `football { trap { ... } }`.
  void UseTrap(const std::string& trap_fields) {
    const std::string text = absl::StrCat("base_config: \"", RepoPath(kShippedTrap),
                                          "\"\nfootball {\n  trap { ", trap_fields, " }\n}\n");
    Use(WriteTemp("football_trap_variant.textproto", text));
  }

  std::unique_ptr<FootballEnv> NewEnv(uint64_t seed) {
    std::unique_ptr<Env> env = spec_->NewEnv(Rng(seed));
    env->Reset(*walk_);
    return std::unique_ptr<FootballEnv>(static_cast<FootballEnv*>(env.release()));
  }

  static double Metric(const FootballEnv& env, const std::string& name) {
    std::vector<NamedValue> metrics;
    env.AppendEpisodeMetrics(&metrics);
    for (const NamedValue& m : metrics) {
      if (m.name == name) return m.value;
    }
    return NAN;
  }

  std::shared_ptr<const FootballSpec> spec_;
  std::unique_ptr<AdaptiveWalk> walk_;
};

TEST_F(FootballTrapEnvTest, ALobFliesThroughItsMeetingPointInFrontOfThePartWithinTheIntegratorsError) {
  const double g = -spec_->model()->opt.gravity[2];
  int lobs = 0;
  for (uint64_t seed = 1; seed <= 12; ++seed) {
    const std::unique_ptr<FootballEnv> env = NewEnv(seed);
    const TrapEpisode& e = env->state().trap;
    if (e.pass.kind != PassKind::kLob) {
      EXPECT_EQ(e.part, config::FOOT) << "ground passes go to the foot";
      continue;
    }
    ++lobs;
    // The analytic flight passes through the meeting point at meet_s.
    const double t = e.pass.meet_s;
    for (int c = 0; c < 3; ++c) {
      const double at = e.pass.start[c] + e.pass.velocity[c] * t - (c == 2 ? 0.5 * g * t * t : 0);
      EXPECT_NEAR(at, e.meet_point[c], 1e-9) << "axis " << c;
    }
    // The meeting point lies beyond the part's surface toward the pass (within the ranges).
    const auto& centre = spec_->trap_bodies().standing_centre[e.part];
    const double out = std::hypot(e.meet_point[0] - centre[0], e.meet_point[1] - centre[1]);
    EXPECT_GE(out, spec_->trap_bodies().bounds[e.part].thinnest() + spec_->ball().radius - 1e-9);
    EXPECT_LE(out, spec_->trap_bodies().bounds[e.part].thinnest() + spec_->ball().radius + 0.25 + 0.1 + 1e-9);
    EXPECT_GT(e.pass.start[0] - e.meet_point[0], 0) << "the ball starts in front";
    EXPECT_LT(e.pass.velocity[0], 0) << "and comes toward the character";
    // It starts lead_s before the meeting, or at the launch when the flight is shorter.
    EXPECT_LE(e.pass.meet_s, spec_->football().trap().lead_s() + 1e-9);
    if (e.pass.meet_s < spec_->football().trap().lead_s() - 1e-9) {
      EXPECT_NEAR(e.pass.start[2], spec_->football().trap().launch_height_m(), 1e-12);
    }
    // In MuJoCo, before anything touches it, the ball follows the analytic flight (its start
    // corrected for the Euler step's ½·g·dt·t, trap_episode.cc).
    std::vector<float> zero(kNumActions, 0.0f);
    for (int step = 0; step < 200; ++step) {
      if (env->Step(zero.data(), *walk_).outcome != Outcome::kRunning) break;
      if (env->state().trap.first_body >= 0 || env->state().trap.turf_before_touch) break;
      const double s = env->time_s();
      const double* ball = env->data()->qpos + spec_->ball().qpos;
      for (int c = 0; c < 3; ++c) {
        const double at =
            e.pass.start[c] + e.pass.velocity[c] * s - (c == 2 ? 0.5 * g * s * s : 0);
        EXPECT_NEAR(ball[c], at, 1e-6) << "seed " << seed << " axis " << c << " t " << s;
      }
    }
  }
  EXPECT_GE(lobs, 6);
}

TEST_F(FootballTrapEnvTest, PartsAreDrawnFromTheListAndGroundPassesRollToTheFoot) {
  UseTrap("parts: HEAD parts: TORSO lob_fraction: 0.5");
  int ground = 0, head = 0, torso = 0;
  for (uint64_t seed = 1; seed <= 40; ++seed) {
    const std::unique_ptr<FootballEnv> env = NewEnv(seed);
    const TrapEpisode& e = env->state().trap;
    if (e.pass.kind == PassKind::kGround) {
      ++ground;
      EXPECT_EQ(e.part, config::FOOT);
      EXPECT_NEAR(env->data()->qpos[spec_->ball().qpos + 2], spec_->ball().radius, 1e-12);
    } else {
      head += e.part == config::HEAD;
      torso += e.part == config::TORSO;
      EXPECT_TRUE(e.part == config::HEAD || e.part == config::TORSO);
    }
  }
  EXPECT_GT(ground, 8);
  EXPECT_GT(head, 4);
  EXPECT_GT(torso, 4);
}

TEST_F(FootballTrapEnvTest, ASnapshotRestoresBitForBitThroughTheTouch) {
  UseTrap("parts: HEAD lob_fraction: 1");
  const std::unique_ptr<FootballEnv> a = NewEnv(5), b = NewEnv(99);
  std::vector<float> act(kNumActions, 0.0f);
  for (int i = 0; i < 10; ++i) a->Step(act.data(), *walk_);
  const std::unique_ptr<EnvSnapshot> snap = a->Snapshot();
  ASSERT_TRUE(b->Restore(*snap).ok());
  Outcome ea = Outcome::kRunning, eb = Outcome::kRunning;
  for (int i = 0; i < 200 && ea == Outcome::kRunning; ++i) {
    for (int k = 0; k < kNumActions; ++k) act[k] = 0.1f * std::sin(0.3f * i + k);
    ea = a->Step(act.data(), *walk_).outcome;
    eb = b->Step(act.data(), *walk_).outcome;
  }
  EXPECT_EQ(ea, eb);
  EXPECT_NE(ea, Outcome::kRunning);
  for (int q = 0; q < spec_->model()->nq; ++q) EXPECT_EQ(a->data()->qpos[q], b->data()->qpos[q]);
  EXPECT_EQ(a->state().trap.first_body, b->state().trap.first_body);
  EXPECT_EQ(a->state().trap.attempt.relative_speed_after_touch,
            b->state().trap.attempt.relative_speed_after_touch);
}

// Drops the ball 0.3 m above the standing head, at rest, and steps with zero action.
Outcome DropOnTheHead(FootballEnv* env, const FootballSpec& spec, const AdaptiveWalk& walk) {
  mjData* d = env->data();
  const auto& head = spec.trap_bodies().standing_centre[config::HEAD];
  double* ball = d->qpos + spec.ball().qpos;
  ball[0] = head[0];
  ball[1] = head[1];
  ball[2] = head[2] + 0.3;
  for (int k = 0; k < 6; ++k) d->qvel[spec.ball().dof + k] = 0;
  mj_forward(spec.model(), d);
  std::vector<float> zero(kNumActions, 0.0f);
  Outcome end = Outcome::kRunning;
  for (int i = 0; i < 100 && end == Outcome::kRunning; ++i) end = env->Step(zero.data(), walk).outcome;
  return end;
}

TEST_F(FootballTrapEnvTest, ABallDroppedOnTheHeadIsATrapForTheHeadAndAWrongPartForTheFoot) {
  UseTrap("parts: HEAD lob_fraction: 1 settle_s: 0.2 reach_m: 3");
  std::unique_ptr<FootballEnv> env = NewEnv(3);
  ASSERT_EQ(env->state().trap.part, config::HEAD);
  EXPECT_EQ(DropOnTheHead(env.get(), *spec_, *walk_), kTrapped);
  EXPECT_EQ(env->state().trap.first_body, spec_->trap_bodies().body[config::HEAD]);
  EXPECT_EQ(env->state().trap.attempt.relative_speed_after_touch.size(),
            static_cast<size_t>(kRelativeSpeedFrames));
  EXPECT_EQ(Metric(*env, "trap_success"), 1);
  EXPECT_EQ(Metric(*env, "trap_touch_before_ground"), 1);
  EXPECT_EQ(Metric(*env, "trap_handball"), 0);
  EXPECT_EQ(Metric(*env, "trap_arms_touched"), 0);
  EXPECT_GT(Metric(*env, "trap_rbspt_mps"), 0);
  EXPECT_EQ(env->completions(), 1);

  UseTrap("parts: FOOT lob_fraction: 1");
  env = NewEnv(3);
  EXPECT_EQ(DropOnTheHead(env.get(), *spec_, *walk_), kWrongPart);
  EXPECT_EQ(Metric(*env, "trap_success"), 0);
  EXPECT_EQ(Metric(*env, "trap_touch_before_ground"), 1) << "seed 002's success: any part first";
  EXPECT_EQ(env->completions(), 0);
}

TEST_F(FootballTrapEnvTest, ABallThatMeetsTheTurfFirstEndsAsGroundFirst) {
  UseTrap("parts: HEAD lob_fraction: 1");
  const std::unique_ptr<FootballEnv> env = NewEnv(4);
  mjData* d = env->data();
  double* ball = d->qpos + spec_->ball().qpos;
  ball[0] = 2;  // far in front of the character
  ball[1] = 0;
  ball[2] = 0.5;
  for (int k = 0; k < 6; ++k) d->qvel[spec_->ball().dof + k] = 0;
  mj_forward(spec_->model(), d);
  std::vector<float> zero(kNumActions, 0.0f);
  Outcome end = Outcome::kRunning;
  for (int i = 0; i < 100 && end == Outcome::kRunning; ++i) end = env->Step(zero.data(), *walk_).outcome;
  EXPECT_EQ(end, kGroundFirst);
  EXPECT_EQ(Metric(*env, "trap_touch_before_ground"), 0);
}

TEST_F(FootballTrapEnvTest, PassesThatCannotReachThePartAreRefusedNamingFileLineAndField) {
  const std::string weak =
      absl::StrCat("base_config: \"", RepoPath(kShippedTrap),
                   "\"\nfootball {\n  trap {\n    parts: HEAD\n    launch_speed_max_mps: 3\n"
                   "    launch_speed_min_mps: 2\n  }\n}\n");
  const std::string path = WriteTemp("football_trap_weak.textproto", weak);
  absl::StatusOr<LoadedConfig> c = LoadRunConfig(path);
  ASSERT_TRUE(c.ok()) << c.status();
  absl::StatusOr<std::shared_ptr<const EnvSpec>> spec = CreateEnvSpec(*c);
  ASSERT_FALSE(spec.ok());
  EXPECT_THAT(std::string(spec.status().message()),
              StartsWith(Loc(path, weak, "launch_speed_max_mps")));
  EXPECT_THAT(spec.status().message(), HasSubstr("cannot come down through"));

  const std::string reversed = absl::StrCat(
      "base_config: \"", RepoPath(kShippedTrap),
      "\"\nfootball {\n  trap {\n    meet_ahead_min_m: 0.5\n    meet_ahead_max_m: 0.1\n  }\n}\n");
  const std::string path2 = WriteTemp("football_trap_reversed.textproto", reversed);
  c = LoadRunConfig(path2);
  ASSERT_TRUE(c.ok()) << c.status();
  spec = CreateEnvSpec(*c);
  ASSERT_FALSE(spec.ok());
  EXPECT_THAT(std::string(spec.status().message()), StartsWith(Loc(path2, reversed, "meet_ahead_min_m")));
}

TEST_F(FootballTrapEnvTest, ADesignatedPartTheModelLacksIsRefusedNamingFileLineAndField) {
  // The pitch with the head's geom renamed, in the test's temp folder.
  std::string humanoid = ::juggle::testing::ReadRepoFile("configs/models/humanoid.xml");
  const size_t at = humanoid.find("name=\"head\"");
  ASSERT_NE(at, std::string::npos);
  humanoid.replace(at, 11, "name=\"noggin\"");
  WriteTemp("humanoid.xml", humanoid);
  WriteTemp("football_ball.xml",
            ::juggle::testing::ReadRepoFile("configs/models/football_ball.xml"));
  const std::string pitch = WriteTemp(
      "headless_pitch.xml", ::juggle::testing::ReadRepoFile("configs/models/football_pitch.xml"));
  const std::string text =
      absl::StrCat("base_config: \"", RepoPath(kShippedTrap), "\"\nfootball {\n  model_file: \"",
                   pitch, "\"\n  trap {\n    parts: TORSO\n    parts: HEAD\n  }\n}\n");
  const std::string path = WriteTemp("football_trap_headless.textproto", text);
  absl::StatusOr<LoadedConfig> c = LoadRunConfig(path);
  ASSERT_TRUE(c.ok()) << c.status();
  absl::StatusOr<std::shared_ptr<const EnvSpec>> spec = CreateEnvSpec(*c);
  ASSERT_FALSE(spec.ok());
  EXPECT_THAT(std::string(spec.status().message()), StartsWith(Loc(path, text, "parts", 1)));
  EXPECT_THAT(spec.status().message(), HasSubstr("no geom 'head'"));
}

}  // namespace
}  // namespace juggle::football

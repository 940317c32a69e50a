// Each skill by search on a hand-made state its base controller misses: a foot kick, a knee
// kick and a header, rescued by the planner and executed exactly as predicted.
#include <cmath>
#include <memory>
#include <optional>
#include <string>

#include "common/adaptive_walk.h"
#include "envs/registry.h"
#include "envs/testing/test_configs.h"
#include "gtest/gtest.h"
#include "planner/receding_horizon.h"
#include "planner/soccer_juggle/cost.h"
#include "planner/soccer_juggle/task.h"
#include "planner/soccer_juggle/test_kicks.h"

namespace juggle::planner {
namespace {

using soccer_juggle::JuggleEnv;
using soccer_juggle::JuggleSpec;
using soccer_juggle::kNumActions;

struct Skill {
  std::string config;  // a shipped run config
  std::string node;    // the DOWN node the episode starts in
  double ahead;        // m the ball is moved forward from the node's start
  double left;         // m the ball is moved to the character's left
  uint64_t env_seed;
};

class SkillRescueTest : public ::testing::TestWithParam<Skill> {
 protected:
  void SetUp() override {
    absl::StatusOr<LoadedConfig> config =
        LoadRunConfig(::juggle::testing::RepoPath(GetParam().config));
    ASSERT_TRUE(config.ok()) << config.status();
    config_ = *config;
    UseSmallPlanner(&config_);
    absl::StatusOr<std::shared_ptr<const EnvSpec>> spec = CreateEnvSpec(config_);
    ASSERT_TRUE(spec.ok()) << spec.status();
    spec_ = std::dynamic_pointer_cast<const JuggleSpec>(*spec);
    walk_ = std::make_unique<AdaptiveWalk>(&spec_->graph());
    pool_ = std::make_unique<RolloutPool>(spec_, 2);
    const std::optional<int> node = spec_->graph().FindNode(GetParam().node);
    ASSERT_TRUE(node.has_value()) << GetParam().node;
    down_ = *node;
  }

  std::unique_ptr<JuggleEnv> Start() const {
    auto env = std::make_unique<JuggleEnv>(spec_, Rng(GetParam().env_seed));
    env->ResetAt(down_, *walk_);
    mjData* d = env->data();
    d->qpos[spec_->ball_qpos()] += GetParam().ahead;
    d->qpos[spec_->ball_qpos() + 1] += GetParam().left;
    mj_forward(spec_->model(), d);
    return env;
  }

  LoadedConfig config_;
  std::shared_ptr<const JuggleSpec> spec_;
  std::unique_ptr<AdaptiveWalk> walk_;
  std::unique_ptr<RolloutPool> pool_;
  int down_ = -1;
};

TEST_P(SkillRescueTest, RescuesAKickTheBaseControllerMissesExactlyAsPredicted) {
  const KickOutcome base = ZeroActionKick(Start().get(), *walk_);
  ASSERT_TRUE(!base.valid || std::abs(base.timing) > 0.06 || std::hypot(base.dx, base.dy) > 0.3)
      << "the hand-made state should defeat the base controller: timing " << base.timing
      << " landing " << base.dx << " " << base.dy;

  std::unique_ptr<JuggleEnv> env = Start();
  config::PlannerConfig p = config_.run.planner();
  p.set_seed(1);
  RecedingHorizonPlanner planner(std::make_shared<SoccerJuggleTask>(spec_, p), p, pool_.get(), 0);
  float action[kNumActions];
  KickOutcome predicted, executed;
  for (int t = 0; t < 60 && !executed.valid; ++t) {
    ASSERT_TRUE(planner.Act(*env, action).ok());
    const ReplanReport& r = planner.last_replan();
    if (r.env_step == env->steps() && KickOutcomeOf(r.predicted_outcome).valid) {
      predicted = KickOutcomeOf(r.predicted_outcome);
    }
    ASSERT_EQ(env->Step(action, *walk_).outcome, Outcome::kRunning) << "step " << t;
    if (env->state().kick_touched && !env->state().touched_this_step) {
      executed = PredictKickOutcome(*env);
    }
  }
  ASSERT_TRUE(executed.valid);
  ASSERT_TRUE(predicted.valid);
  // Bit for bit: the last plan made before the ball left the body is what happened.
  EXPECT_EQ(executed.timing, predicted.timing);
  EXPECT_EQ(executed.dx, predicted.dx);
  EXPECT_EQ(executed.dy, predicted.dy);
  // And the ball comes back inside the contact window, near the next node's ball target.
  EXPECT_LT(std::abs(executed.timing), 0.06);
  EXPECT_LT(std::hypot(executed.dx, executed.dy), 0.15);
  EXPECT_EQ(planner.totals().prediction_mismatches, 0);
  EXPECT_GT(planner.totals().prediction_checks, 5);
}

INSTANTIATE_TEST_SUITE_P(
    Skills, SkillRescueTest,
    // The knee's state: 6 cm ahead, scanned among 4-8 cm ahead and 5 cm sideways on start
    // seeds 3-4 (some of which the base controller already returns, or the small search
    // here does not rescue).
    // The foot's state: 12 cm too far forward, its base kick flies off.
    // The header's: 8 cm behind (8 cm ahead the head feedback now returns the ball itself, to
    // 0.21 m; 12-20 cm ahead this small search leaves it 0.16-0.34 m off).
    ::testing::Values(Skill{"configs/right_foot_planner.textproto", "right_foot_down", 0.12, 0, 3},
                      Skill{"configs/knees_planner.textproto", "right_knee_down", 0.06, 0, 3},
                      Skill{"configs/headers_planner.textproto", "head_down", -0.08, 0, 3}),
    [](const ::testing::TestParamInfo<Skill>& info) {
      return info.param.node.substr(0, info.param.node.find("_down"));
    });

}  // namespace
}  // namespace juggle::planner

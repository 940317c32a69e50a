// The evaluation loop: batched episodes equal episodes run alone (an independent path), every
// episode ends with its result filled in, recordings hold each episode in turn, and rollouts
// reset at episode ends.
#include "eval/episode_runner.h"

#include <memory>

#include "envs/registry.h"
#include "envs/testing/test_configs.h"
#include "gtest/gtest.h"

namespace juggle {
namespace {

std::shared_ptr<const EnvSpec> Spec(const std::string& name) {
  absl::StatusOr<LoadedConfig> config = testing::LoadShippedConfig(name);
  if (!config.ok()) return nullptr;
  absl::StatusOr<std::shared_ptr<const EnvSpec>> spec = CreateEnvSpec(*config);
  EXPECT_TRUE(spec.ok()) << spec.status();
  return spec.ok() ? *spec : nullptr;
}

// Pseudo-random actions from each env's own observation: a controller whose episodes differ.
class HashController final : public Controller {
 public:
  HashController(int obs_dim, int act_dim) : obs_dim_(obs_dim), act_dim_(act_dim) {}
  void Act(const Env* const*, const float* obs, int n, float* actions) override {
    for (int i = 0; i < n; ++i) {
      const float* o = obs + static_cast<size_t>(i) * obs_dim_;
      for (int a = 0; a < act_dim_; ++a) {
        actions[i * act_dim_ + a] = std::sin((o[0] + o[obs_dim_ - 1]) * (a + 1) * 13.0f);
      }
    }
  }
  std::string name() const override { return "hash"; }

 private:
  int obs_dim_, act_dim_;
};

// Episodes first .. first + n - 1 of seed 77 on foot_variable_height under the hash controller.
absl::StatusOr<EpisodeReport> HashEpisodes(int n, int first = 0) {
  auto spec = Spec("foot_variable_height");
  if (spec == nullptr) return absl::InternalError("foot_variable_height did not load");
  HashController controller(spec->obs_dim(), spec->act_dim());
  EpisodeOptions o;
  o.episodes = n;
  o.seed = 77;
  o.first_episode = first;
  return RunEpisodes(spec, &controller, o);
}

TEST(EpisodeRunnerTest, BatchedEpisodesEqualTheSameEpisodesRunAlone) {
  absl::StatusOr<EpisodeReport> together = HashEpisodes(4);
  ASSERT_TRUE(together.ok()) << together.status();
  absl::StatusOr<EpisodeReport> first = HashEpisodes(1);
  ASSERT_TRUE(first.ok());
  EXPECT_EQ(first->episodes[0].steps, together->episodes[0].steps);
  EXPECT_EQ(first->episodes[0].return_sum, together->episodes[0].return_sum);
  EXPECT_EQ(first->episodes[0].outcome, together->episodes[0].outcome);
}

TEST(EpisodeRunnerTest, AnEvaluationSplitIntoPartsHasTheEpisodesOfTheWhole) {
  absl::StatusOr<EpisodeReport> all = HashEpisodes(4);
  ASSERT_TRUE(all.ok()) << all.status();
  absl::StatusOr<EpisodeReport> tail = HashEpisodes(2, /*first=*/2);
  ASSERT_TRUE(tail.ok()) << tail.status();
  for (int i = 0; i < 2; ++i) {
    EXPECT_EQ(tail->episodes[i].steps, all->episodes[2 + i].steps) << i;
    EXPECT_EQ(tail->episodes[i].return_sum, all->episodes[2 + i].return_sum) << i;
  }
  // The parts differ from the whole's first episodes (the streams are not reused).
  EXPECT_NE(tail->episodes[0].return_sum, all->episodes[0].return_sum);
  EXPECT_EQ(HashEpisodes(2, /*first=*/-1).status().code(), absl::StatusCode::kInvalidArgument);
}

TEST(EpisodeRunnerTest, ZeroActionRightFootEpisodesEndBallLostAfterTheFirstDescent) {
  auto spec = Spec("right_foot");
  ASSERT_NE(spec, nullptr);
  ZeroController zero(spec->act_dim());
  EpisodeOptions o;
  o.episodes = 3;
  absl::StatusOr<EpisodeReport> report = RunEpisodes(spec, &zero, o);
  ASSERT_TRUE(report.ok()) << report.status();
  ASSERT_EQ(report->episodes.size(), 3u);
  for (const EpisodeResult& e : report->episodes) {
    EXPECT_EQ(OutcomeName(spec->outcome_names(), e.outcome), "ball_lost");
    EXPECT_GT(e.steps, 0);
    EXPECT_EQ(e.juggles, 0);  // the ball was never sent back up
    EXPECT_GT(e.return_sum, 0);
  }
}

TEST(EpisodeRunnerTest, RecordingHoldsEachEpisodeInTurnWithTheFamilyChannels) {
  auto spec = Spec("right_foot");
  ASSERT_NE(spec, nullptr);
  ZeroController zero(spec->act_dim());
  EpisodeOptions o;
  o.episodes = 2;
  o.record = true;
  o.config_path = "configs/right_foot.textproto";
  absl::StatusOr<EpisodeReport> report = RunEpisodes(spec, &zero, o);
  ASSERT_TRUE(report.ok());
  ASSERT_TRUE(report->trajectory.has_value());
  const Trajectory& t = *report->trajectory;
  EXPECT_EQ(t.family, "soccer_juggle");
  EXPECT_EQ(t.nq, spec->model()->nq);
  EXPECT_GE(t.FindChannel("node"), 0);
  EXPECT_GE(t.FindChannel("phase"), 0);
  // One sample per step plus the reset sample, per episode.
  EXPECT_EQ(t.num_samples(), report->episodes[0].steps + 1 + report->episodes[1].steps + 1);
  EXPECT_EQ(t.Label(t.EpisodeEnd(0), kOutcomeChannel), "ball_lost");
  EXPECT_EQ(t.episode(t.num_samples() - 1), 1);
}

TEST(EpisodeRunnerTest, RolloutResetsAtEpisodeEndsAndCoversTheTime) {
  auto spec = Spec("right_foot");
  ASSERT_NE(spec, nullptr);
  ZeroController zero(spec->act_dim());
  absl::StatusOr<Trajectory> t = RecordRollout(spec, &zero, 1.2, 1, -1, "c");
  ASSERT_TRUE(t.ok()) << t.status();
  EXPECT_NEAR(t->duration(), 1.2, 1e-9);
  // Zero action loses the ball after 0.5 s: episodes 0, 1 and part of 2.
  EXPECT_EQ(t->episode(t->num_samples() - 1), 2);
  EXPECT_EQ(t->Label(t->EpisodeEnd(0), kOutcomeChannel), "ball_lost");
}

TEST(EpisodeRunnerTest, StartNodeOfAFamilyWithoutAGraphIsAnError) {
  auto spec = Spec("toss_catch");
  ASSERT_NE(spec, nullptr);
  ZeroController zero(spec->act_dim());
  EpisodeOptions o;
  o.episodes = 1;
  o.start_node = 0;
  EXPECT_EQ(RunEpisodes(spec, &zero, o).status().code(), absl::StatusCode::kInvalidArgument);
}

}  // namespace
}  // namespace juggle

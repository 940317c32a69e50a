// The memory of solved kicks: its file is read strictly (errors name file and line), its
// neighbours are the nearest in the cost's scales, the recorder pairs each kick's incoming ball
// with the variables that kicked it, and the task seeds the search with them only while the
// ball flies to the next contact.
#include "planner/soccer_juggle/kick_memory.h"

#include <memory>
#include <string>
#include <vector>

#include "common/outcome.h"
#include "envs/registry.h"
#include "envs/testing/test_configs.h"
#include "gtest/gtest.h"
#include "planner/kick_memory_recorder.h"
#include "planner/planner_controller.h"
#include "planner/soccer_juggle/cost.h"
#include "planner/soccer_juggle/task.h"

namespace juggle::planner {
namespace {

using soccer_juggle::JuggleEnv;
using soccer_juggle::JuggleSpec;
using soccer_juggle::kNumActions;

using ::juggle::testing::WriteTemp;

TEST(KickMemoryTest, ReadsRowsSkippingCommentsAndNamesTheLineOfABadOne) {
  const config::PlannerCost cost;
  const std::string good = WriteTemp(
      "good.txt", "# a comment\n\n0.01 0.02 -0.03 0 0.1 0  0.02 0.1 -0.1 0.2 0  # kick one\n"
                  "0 0 0 0 0 0 -0.01 0 0 0 0.3\n");
  absl::StatusOr<KickMemory> memory = KickMemory::Load(good, cost);
  ASSERT_TRUE(memory.ok()) << memory.status();
  EXPECT_EQ(memory->size(), 2);

  const std::string short_row = WriteTemp("short.txt", "# header\n0 0 0 0 0 0 1 2 3 4\n");
  absl::StatusOr<KickMemory> bad = KickMemory::Load(short_row, cost);
  ASSERT_FALSE(bad.ok());
  EXPECT_EQ(bad.status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_NE(bad.status().message().find(short_row + ":2:"), std::string::npos) << bad.status();
  EXPECT_NE(bad.status().message().find("10 numbers, expected 11"), std::string::npos);

  const std::string nan = WriteTemp("nan.txt", "0 0 0 0 0 0 1 2 nan 4 5\n");
  bad = KickMemory::Load(nan, cost);
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.status().message().find(nan + ":1: field 9 'nan'"), std::string::npos)
      << bad.status();

  EXPECT_FALSE(KickMemory::Load(WriteTemp("empty.txt", "# nothing\n"), cost).ok());
  EXPECT_EQ(KickMemory::Load("/nonexistent/memory.txt", cost).status().code(),
            absl::StatusCode::kNotFound);
}

TEST(KickMemoryTest, NeighboursAreNearestInTheCostsScales) {
  config::PlannerCost cost;
  cost.set_timing_scale_s(0.03);
  cost.set_landing_scale(0.05);
  // Row a is 0.06 s off in timing (2 scales); row b 0.05 m off in dx (1 scale): b is nearer,
  // though a is nearer in plain units.
  const KickDecision a_kick = {0.01, 0, 0, 0, 0}, b_kick = {0.02, 0, 0, 0, 0};
  KickMemory memory({{KickContext{0.06, 0, 0, 0, 0, 0}, a_kick},
                     {KickContext{0, 0.05, 0, 0, 0, 0}, b_kick}},
                    cost);
  const std::vector<KickDecision> nearest = memory.Nearest(KickContext{}, 5);
  ASSERT_EQ(nearest.size(), 2u);
  EXPECT_EQ(nearest[0], b_kick);
  EXPECT_EQ(nearest[1], a_kick);
  EXPECT_EQ(memory.Nearest(KickContext{0.06, 0, 0, 0, 0, 0}, 1).front(), a_kick);
}

class KickMemoryPlannerTest : public ::testing::Test {
 protected:
  void SetUp() override {
    absl::StatusOr<LoadedConfig> config =
        LoadRunConfig(::juggle::testing::RepoPath("configs/right_foot_planner.textproto"));
    ASSERT_TRUE(config.ok()) << config.status();
    config_ = *config;
    config::PlannerConfig& p = *config_.run.mutable_planner();
    p.set_samples(8);
    p.set_iterations(1);
    p.set_horizon_steps(24);
    p.set_replan_every(3);
    p.set_body_knot_steps(0);
    p.mutable_rescue()->set_cost_above(0);
    absl::StatusOr<std::shared_ptr<const EnvSpec>> spec = CreateEnvSpec(config_);
    ASSERT_TRUE(spec.ok()) << spec.status();
    spec_ = std::dynamic_pointer_cast<const JuggleSpec>(*spec);
    walk_ = std::make_unique<AdaptiveWalk>(&spec_->graph());
  }

  LoadedConfig config_;
  std::shared_ptr<const JuggleSpec> spec_;
  std::unique_ptr<AdaptiveWalk> walk_;
};

// Two seconds of the planner juggling with the recorder around it: one row per release after
// the first, each pairing the context seen at the previous release (computed here from the
// env) with the planner's last decision before this release.
TEST_F(KickMemoryPlannerTest, TheRecorderPairsEachKicksIncomingBallWithTheVariablesThatKickedIt) {
  absl::StatusOr<std::unique_ptr<PlannerController>> planner =
      PlannerController::Create(spec_, config_);
  ASSERT_TRUE(planner.ok()) << planner.status();
  KickMemoryRecorder recorder(planner->get(), planner->get());
  JuggleEnv env(spec_, Rng::ForStream(1000000, 0, 1));
  env.Reset(*walk_);
  std::vector<std::string> expected;
  std::optional<KickContext> incoming;
  bool was_released = false;
  float action[kNumActions];
  bool running = true;
  for (int t = 0; t < 2 * 60 && running; ++t) {
    const std::optional<KickContext> context = KickContextOf(env);
    if (context.has_value() && !was_released) {
      const std::vector<double>& d = (*planner)->PlannerFor(env).last_replan().decision;
      if (incoming.has_value()) {
        expected.push_back(FormatKickMemoryRow(*incoming, {d[0], d[1], d[2], d[3], d[4]}));
      }
      incoming = context;
    }
    was_released = context.has_value();
    const Env* batch[1] = {&env};
    recorder.Act(batch, nullptr, 1, action);
    running = env.Step(action, *walk_).outcome == Outcome::kRunning;
  }
  ASSERT_GE(expected.size(), 1u) << "two seconds should hold at least two kicks";
  EXPECT_EQ(recorder.rows(), expected);
  // The file it writes reads back as a memory of as many kicks.
  absl::StatusOr<KickMemory> memory = KickMemory::Load(
      WriteTemp("recorded.txt", recorder.FileText()), config_.run.planner().soccer_juggle().cost());
  ASSERT_TRUE(memory.ok()) << memory.status();
  EXPECT_EQ(memory->size(), static_cast<int>(expected.size()));
}

// The task appends one seed per neighbour, the warm start with the next kick's set replaced
// (clamped to the box), only while the ball is in free flight after a touch.
TEST_F(KickMemoryPlannerTest, RememberedKicksSeedTheSearchOnlyWhileTheBallFlies) {
  const std::string file = WriteTemp("memory.txt",
                                     "0 0 0 0 0 0  0.03 0.1 -0.2 0.3 9\n"
                                     "1 1 1 1 1 1  -0.02 0 0 0 0\n");
  config::PlannerConfig p = config_.run.planner();
  p.mutable_soccer_juggle()->mutable_kick_memory()->set_file(file);
  p.mutable_soccer_juggle()->mutable_kick_memory()->set_neighbours(1);
  const SoccerJuggleTask task(spec_, p);
  const std::vector<double> warm(task.dim(), 0.01);
  auto seeds_at = [&](const JuggleEnv& env) {
    SearchSpace space = task.space();
    std::vector<std::vector<double>> seeds = task.Seeds(warm);
    task.Restrict(env, warm, &space, &seeds);
    return seeds;
  };
  JuggleEnv env(spec_, Rng::ForStream(1000000, 0, 1));
  env.Reset(*walk_);
  const size_t plain = task.Seeds(warm).size();
  ASSERT_FALSE(KickContextOf(env).has_value());
  EXPECT_EQ(seeds_at(env).size(), plain) << "before the first touch nothing is remembered";
  // Zero action until the ball has left the foot.
  const float zero[kNumActions] = {0};
  for (int t = 0; t < 120 && !KickContextOf(env).has_value(); ++t) {
    ASSERT_EQ(env.Step(zero, *walk_).outcome, Outcome::kRunning);
  }
  ASSERT_TRUE(KickContextOf(env).has_value());
  const std::vector<std::vector<double>> seeds = seeds_at(env);
  ASSERT_EQ(seeds.size(), plain + 1);
  const double limit = task.space().upper[4];
  const std::vector<double> want = {0.03, 0.1, -0.2, 0.3, limit};  // 9 rad clamped
  EXPECT_EQ(std::vector<double>(seeds.back().begin(), seeds.back().begin() + 5), want);
  EXPECT_EQ(std::vector<double>(seeds.back().begin() + 5, seeds.back().end()),
            std::vector<double>(warm.begin() + 5, warm.end()));
}

TEST_F(KickMemoryPlannerTest, AMemoryFileThatDoesNotReadIsAConfigErrorAtItsField) {
  config_.run.mutable_planner()->mutable_soccer_juggle()->mutable_kick_memory()->set_file(
      WriteTemp("bad.txt", "0 0 0\n"));
  const absl::Status status = ValidateSoccerJuggleTask(config_);
  ASSERT_FALSE(status.ok());
  EXPECT_NE(status.message().find("kick_memory.file"), std::string::npos) << status;
  EXPECT_NE(status.message().find(":1: 3 numbers"), std::string::npos) << status;
}

// MinimizeCem drops the seeds its first iteration cannot hold, so a memory whose neighbours
// (with the warm start, the nominal kick and, in a rescue, the troubled plan) outnumber a
// search's samples is refused at its field rather than partly ignored.
TEST_F(KickMemoryPlannerTest, MoreRememberedKicksThanASearchHoldsAreAConfigErrorAtNeighbours) {
  const std::string file = WriteTemp("memory.txt", "0 0 0 0 0 0  0.03 0.1 -0.2 0.3 0\n");
  config::PlannerConfig& p = *config_.run.mutable_planner();
  p.mutable_soccer_juggle()->mutable_kick_memory()->set_file(file);
  p.mutable_soccer_juggle()->mutable_kick_memory()->set_neighbours(6);  // 8 seeds, 8 samples
  EXPECT_TRUE(ValidateSoccerJuggleTask(config_).ok()) << ValidateSoccerJuggleTask(config_);
  p.mutable_soccer_juggle()->mutable_kick_memory()->set_neighbours(7);
  absl::Status status = ValidateSoccerJuggleTask(config_);
  ASSERT_FALSE(status.ok());
  EXPECT_NE(status.message().find("neighbours"), std::string::npos) << status;
  EXPECT_NE(status.message().find(": 7 remembered kicks"), std::string::npos) << status;
  EXPECT_NE(status.message().find("more than the 8 samples of planner.samples"), std::string::npos)
      << status;
  // A rescue's first iteration also holds the troubled plan: 2 neighbours fit 4 samples of
  // the rescue only without it.
  p.mutable_soccer_juggle()->mutable_kick_memory()->set_neighbours(2);
  p.mutable_rescue()->set_cost_above(1000);
  p.mutable_rescue()->set_narrowed_samples(4);
  status = ValidateSoccerJuggleTask(config_);
  ASSERT_FALSE(status.ok());
  EXPECT_NE(status.message().find("the rescue's first iteration"), std::string::npos) << status;
  p.mutable_soccer_juggle()->mutable_kick_memory()->set_neighbours(1);
  EXPECT_TRUE(ValidateSoccerJuggleTask(config_).ok()) << ValidateSoccerJuggleTask(config_);
}

}  // namespace
}  // namespace juggle::planner

// The evaluation tables: per-node counts from real soccer episodes (zero action: every episode
// completes its first DOWN node, then fails in the UP node), the node table's arithmetic and
// text, the force sweep through the family hook (toss: wind along x only; soccer: the ball
// force), and the JSON lines.
#include "eval/tables.h"

#include <numeric>

#include "envs/registry.h"
#include "envs/testing/test_configs.h"
#include "gmock/gmock.h"
#include "gtest/gtest.h"
#include "nlohmann/json.hpp"

namespace juggle {
namespace {

// The zero-action controller for every swept config.
ControllerFactory ZeroControllers(int act_dim) {
  return [act_dim](std::shared_ptr<const EnvSpec>, const LoadedConfig&)
             -> absl::StatusOr<std::unique_ptr<Controller>> {
    return std::make_unique<ZeroController>(act_dim);
  };
}

using ::testing::HasSubstr;

int ActDim(const LoadedConfig& config) {
  absl::StatusOr<std::shared_ptr<const EnvSpec>> spec = CreateEnvSpec(config);
  EXPECT_TRUE(spec.ok()) << spec.status();
  return spec.ok() ? (*spec)->act_dim() : 0;
}

LoadedConfig EvalConfig(const std::string& name, double max_seconds) {
  absl::StatusOr<LoadedConfig> c = testing::LoadShippedConfig(name);
  EXPECT_TRUE(c.ok());
  (*FamilyOf(c->run))->ConfigureForEvaluation(max_seconds, &c->run);
  return *c;
}

// Three episodes of `spec` with zero action, streams 0-2.
absl::StatusOr<EpisodeReport> ThreeZeroActionEpisodes(std::shared_ptr<const EnvSpec> spec) {
  ZeroController zero(spec->act_dim());
  EpisodeOptions o;
  o.episodes = 3;
  return RunEpisodes(spec, &zero, o);
}

TEST(TablesTest, ZeroActionEpisodesCompleteTheDownNodeAndFailInTheUpNode) {
  absl::StatusOr<std::shared_ptr<const EnvSpec>> spec = CreateEnvSpec(EvalConfig("right_foot", 10));
  ASSERT_TRUE(spec.ok()) << spec.status();
  absl::StatusOr<EpisodeReport> report = ThreeZeroActionEpisodes(*spec);
  ASSERT_TRUE(report.ok()) << report.status();
  for (const EpisodeResult& e : report->episodes) {
    ASSERT_EQ(e.node_visits.size(), 2u);
    EXPECT_EQ(std::accumulate(e.node_completions.begin(), e.node_completions.end(), 0),
              e.completions);
  }
  const std::vector<NodeRow> rows =
      NodeTable(report->episodes, (*spec)->graph(), (*spec)->outcome_names());
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_EQ(rows[0].node, "right_foot_down");
  EXPECT_EQ(rows[0].visits, 3);
  EXPECT_EQ(rows[0].completions, 3);
  EXPECT_DOUBLE_EQ(rows[0].success_rate, 1.0);
  EXPECT_TRUE(rows[0].endings.empty());
  EXPECT_EQ(rows[1].node, "right_foot_up");
  EXPECT_EQ(rows[1].visits, 3);
  EXPECT_EQ(rows[1].completions, 0);
  int ended = 0;
  for (const auto& [name, count] : rows[1].endings) ended += count;
  EXPECT_EQ(ended, 3);
}

TEST(TablesTest, TheEdgeTableAgreesWithTheNodeTableForANodeEnteredOnlyByItsEdges) {
  // The env's walk events counted per edge against the runner's own per-node counting: the
  // UP node is never a start, so everything in it came through the DOWN -> UP edge.
  absl::StatusOr<std::shared_ptr<const EnvSpec>> spec = CreateEnvSpec(EvalConfig("right_foot", 10));
  ASSERT_TRUE(spec.ok()) << spec.status();
  absl::StatusOr<EpisodeReport> report = ThreeZeroActionEpisodes(*spec);
  ASSERT_TRUE(report.ok()) << report.status();
  const std::vector<NodeRow> nodes =
      NodeTable(report->episodes, (*spec)->graph(), (*spec)->outcome_names());
  const std::vector<EdgeRow> edges = EdgeTable(report->episodes, (*spec)->graph());
  ASSERT_EQ(edges.size(), 2u);
  const EdgeRow& into_up = edges[0].to == "right_foot_up" ? edges[0] : edges[1];
  const EdgeRow& into_down = edges[0].to == "right_foot_up" ? edges[1] : edges[0];
  EXPECT_EQ(into_up.from, "right_foot_down");
  EXPECT_EQ(into_up.chosen, nodes[1].visits);
  EXPECT_EQ(into_up.completed, nodes[1].completions);
  int ended_up = 0;
  for (const auto& [name, count] : nodes[1].endings) ended_up += count;
  EXPECT_EQ(into_up.failed, ended_up);
  EXPECT_EQ(into_down.chosen, 0) << "no episode got back to the DOWN node";
  const nlohmann::json line = nlohmann::json::parse(EdgeRowJson(into_up));
  EXPECT_EQ(line["table"], "edge");
  EXPECT_EQ(line["from"], "right_foot_down");
  EXPECT_EQ(line["chosen"], 3);
  EXPECT_EQ(line["failed"], 3);
}

TEST(TablesTest, NodeTableCountsVisitsCompletionsAndEndingsPerNode) {
  const LoadedConfig config = EvalConfig("foot_and_head", 10);
  const std::vector<std::string> outcomes = {"running", "time_limit", "diverged", "fell"};
  EpisodeResult a, b;
  a.node_visits = {2, 1, 0, 0};
  a.node_completions = {2, 0, 0, 0};
  a.outcome = FamilyOutcome(0);  // fell
  a.end_node = 1;
  b.node_visits = {1, 0, 1, 0};
  b.node_completions = {1, 0, 0, 0};
  b.outcome = Outcome::kTimeLimit;
  b.end_node = 2;
  const std::vector<NodeRow> rows = NodeTable({a, b}, *config.graph, outcomes);
  ASSERT_EQ(rows.size(), static_cast<size_t>(config.graph->num_nodes()));
  EXPECT_EQ(rows[0].visits, 3);
  EXPECT_EQ(rows[0].completions, 3);
  EXPECT_EQ(rows[1].success_rate, 0.0);
  EXPECT_EQ(rows[1].endings.at("fell"), 1);
  EXPECT_EQ(rows[2].endings.at("time_limit"), 1);
  const std::string text = FormatNodeTable(rows);
  EXPECT_THAT(text, HasSubstr("completions  success     fell time_limit"));
  EXPECT_THAT(text, HasSubstr(absl::StrCat(rows[0].node)));
  EXPECT_EQ(nlohmann::json::parse(NodeRowJson(rows[1])),
            nlohmann::json::parse(absl::StrCat(
                "{\"table\":\"node\",\"node\":\"", rows[1].node,
                "\",\"visits\":1,\"completions\":0,\"success_rate\":0,"
                "\"endings\":{\"fell\":1}}")));
}

TEST(TablesTest, FamiliesWithoutAGraphGetOneEpisodeRow) {
  EpisodeResult e;
  e.node_visits = {1};
  e.node_completions = {1};
  e.outcome = Outcome::kTimeLimit;
  const std::vector<NodeRow> rows = NodeTable({e}, ControlGraph(), {"running", "time_limit"});
  ASSERT_EQ(rows.size(), 1u);
  EXPECT_EQ(rows[0].node, "episode");
  EXPECT_DOUBLE_EQ(rows[0].success_rate, 1.0);
}

TEST(TablesTest, EpisodeJsonNamesTheEpisodeItsJugglesSecondsAndEnding) {
  EpisodeResult e;
  e.juggles = 7;
  e.steps = 90;
  e.return_sum = 12.5;
  e.outcome = Outcome::kTimeLimit;
  const nlohmann::json j =
      nlohmann::json::parse(EpisodeJson(13, e, 1.0 / 30, {"running", "time_limit"}));
  EXPECT_EQ(j["table"], "episode");
  EXPECT_EQ(j["episode"], 13);
  EXPECT_EQ(j["juggles"], 7);
  EXPECT_DOUBLE_EQ(j["seconds"].get<double>(), 3.0);
  EXPECT_DOUBLE_EQ(j["return"].get<double>(), 12.5);
  EXPECT_EQ(j["outcome"], "time_limit");
}

TEST(TablesTest, TossSweepsHorizontalWindOnlyAndFindsTheLargestPassingForce) {
  const LoadedConfig config = EvalConfig("toss_catch", 1);
  const ControllerFactory zero = ZeroControllers(ActDim(config));
  ForceSweepOptions o;
  o.magnitudes = {0, 0.5};
  o.min_median_juggles = 0;  // every force passes
  o.episodes.episodes = 2;
  std::vector<std::string> lines;
  absl::StatusOr<ForceSweepReport> r =
      RunForceSweep(config, zero, o, [&](const std::string& l) { lines.push_back(l); });
  ASSERT_TRUE(r.ok()) << r.status();
  EXPECT_EQ(r->rows.size(), 4u);  // ±x × {0, 0.5}
  EXPECT_EQ(r->directions, (std::vector<std::string>{"+x", "-x"}));
  EXPECT_EQ(r->max_force_n.at("+x"), 0.5);
  EXPECT_EQ(r->max_force_n.at("-x"), 0.5);
  ASSERT_EQ(r->unsupported.size(), 4u);
  EXPECT_THAT(r->unsupported.at("+z"), HasSubstr("only horizontal wind"));
  EXPECT_EQ(lines.size(), 8u);

  o.min_median_juggles = 2;  // a catch episode has at most 1 juggle: nothing passes
  r = RunForceSweep(config, zero, o, nullptr);
  ASSERT_TRUE(r.ok()) << r.status();
  EXPECT_EQ(r->max_force_n.at("+x"), -1);
  EXPECT_THAT(ForceRowJson(r->rows[1]),
              HasSubstr("{\"table\":\"force_sweep\",\"direction\":\"+x\",\"force_n\":0.5,"
                        "\"episodes\":2,\"median_juggles\":"));
}

// A baseline the caller has already evaluated is every direction's 0 N row, and no
// controller is made for it; without one the sweep evaluates 0 N once.
TEST(TablesTest, SweepUsesAGivenBaselineForTheZeroForceRows) {
  const LoadedConfig config = EvalConfig("toss_catch", 1);
  int controllers_made = 0;
  const ControllerFactory zero = ZeroControllers(ActDim(config));
  const ControllerFactory counted = [&](std::shared_ptr<const EnvSpec> spec,
                                        const LoadedConfig& c) {
    ++controllers_made;
    return zero(spec, c);
  };
  ForceSweepOptions o;
  o.magnitudes = {0, 0.5};
  o.episodes.episodes = 2;
  absl::StatusOr<ForceSweepReport> r = RunForceSweep(config, counted, o, nullptr);
  ASSERT_TRUE(r.ok()) << r.status();
  EXPECT_EQ(controllers_made, 3);  // 0 N once, then ±x at 0.5 N
  const EvalSummary evaluated = r->rows[0].summary;
  const EvalSummary forced_plus_x = r->rows[1].summary;

  EvalSummary given = evaluated;
  given.median_juggles = 42;  // marks the given summary
  o.baseline = given;
  controllers_made = 0;
  r = RunForceSweep(config, counted, o, nullptr);
  ASSERT_TRUE(r.ok()) << r.status();
  EXPECT_EQ(controllers_made, 2);
  ASSERT_EQ(r->rows.size(), 4u);
  EXPECT_EQ(r->rows[0].summary.median_juggles, 42);  // +x, 0 N
  EXPECT_EQ(r->rows[2].summary.median_juggles, 42);  // -x, 0 N
  // The forced rows are those of the first sweep: the same episodes, deterministic.
  EXPECT_EQ(r->rows[1].summary.mean_return, forced_plus_x.mean_return);
}

TEST(TablesTest, SoccerForceHookSetsTheBallForce) {
  LoadedConfig config = EvalConfig("right_foot", 1);
  const double force[3] = {0, -1.5, 2};
  ASSERT_TRUE((*FamilyOf(config.run))->SetConstantBallForce(force, &config.run).ok());
  const config::Vec3& f = config.run.soccer_juggle().env().ball_force();
  EXPECT_EQ(f.x(), 0);
  EXPECT_EQ(f.y(), -1.5);
  EXPECT_EQ(f.z(), 2);
}

TEST(TablesTest, SweepRefusesDescendingMagnitudes) {
  const LoadedConfig config = EvalConfig("toss_catch", 1);
  const ControllerFactory zero = ZeroControllers(ActDim(config));
  ForceSweepOptions o;
  o.magnitudes = {1, 0.5};
  EXPECT_THAT(RunForceSweep(config, zero, o, nullptr).status().message(),
              HasSubstr("ascending"));
}

}  // namespace
}  // namespace juggle

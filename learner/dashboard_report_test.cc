// `juggle dashboard --eval` (learner/dashboard_report.h, RenderEvalDashboard): an evaluation's
// JSON lines become the page's data with the graph's nodes from the evaluation's node table and
// its edges from the edge lines; a line that is not JSON, an edge the graph lacks and a file
// without edge lines are refused, naming the file and line.
#include "learner/dashboard_report.h"

#include <string>

#include "envs/testing/test_configs.h"
#include "gmock/gmock.h"
#include "gtest/gtest.h"
#include "nlohmann/json.hpp"

namespace juggle {
namespace {

using ::testing::HasSubstr;

// The right foot's two nodes and two edges, as `juggle eval --json` writes them.
constexpr char kEval[] =
    R"({"table":"summary","episodes":3,"median_juggles":1.0,"p10_juggles":1.0,"p90_juggles":2.0,"mean_juggles":1.3,"outcomes":{"ball_lost":3}}
{"table":"node","node":"right_foot_down","visits":5,"completions":4,"success_rate":0.8,"endings":{}}
{"table":"node","node":"right_foot_up","visits":4,"completions":1,"success_rate":0.25,"endings":{"ball_lost":3}}
{"table":"edge","from":"right_foot_down","to":"right_foot_up","chosen":4,"completed":1,"failed":3}
{"table":"edge","from":"right_foot_up","to":"right_foot_down","chosen":1,"completed":1,"failed":0}
{"table":"episode","episode":0,"juggles":1}
{"table":"episode","episode":1,"juggles":2}
{"table":"episode","episode":2,"juggles":1}
)";

// The JSON object assigned to window.JUGGLE_DATA in the page.
nlohmann::json EmbeddedData(const std::string& html) {
  const std::string start = "window.JUGGLE_DATA = ";
  const size_t at = html.find(start);
  EXPECT_NE(at, std::string::npos);
  const size_t end = html.find("};", at);
  return nlohmann::json::parse(html.substr(at + start.size(), end + 1 - at - start.size()));
}

class EvalDashboardTest : public ::testing::Test {
 protected:
  void SetUp() override {
    absl::StatusOr<LoadedConfig> c = testing::LoadShippedConfig("right_foot");
    ASSERT_TRUE(c.ok()) << c.status();
    config_ = *c;
  }
  LoadedConfig config_;
};

TEST_F(EvalDashboardTest, NodesComeFromTheNodeTableAndEdgesFromTheEdgeLines) {
  const std::string path = testing::WriteTemp("eval_dashboard.jsonl", kEval);
  absl::StatusOr<DashboardReport> report = RenderEvalDashboard(path, config_);
  ASSERT_TRUE(report.ok()) << report.status();
  const nlohmann::json data = EmbeddedData(report->html);
  const nlohmann::json& graph = data["status"]["graph"];
  ASSERT_EQ(graph["nodes"].size(), 2u);
  for (const nlohmann::json& n : graph["nodes"]) {
    if (n["name"] == "right_foot_down") {
      EXPECT_DOUBLE_EQ(n["success"].get<double>(), 0.8) << "4 of 5 visits, the starts included";
      EXPECT_EQ(n["entered"], 5);
    } else {
      EXPECT_DOUBLE_EQ(n["success"].get<double>(), 0.25);
    }
    EXPECT_TRUE(n["recent_success"].is_null());
  }
  for (const nlohmann::json& e : graph["edges"]) {
    const bool down_up = graph["nodes"][e["from"].get<int>()]["name"] == "right_foot_down";
    EXPECT_EQ(e["chosen"], down_up ? 4 : 1);
    EXPECT_DOUBLE_EQ(e["success"].get<double>(), down_up ? 0.25 : 1.0);
  }
  EXPECT_EQ(data["evaluation"]["episodes"], 3);
  EXPECT_DOUBLE_EQ(data["evaluation"]["p90_juggles"].get<double>(), 2.0);
  EXPECT_EQ(data["evals"]["evaluations"].size(), 1u);
  EXPECT_EQ(data["evals"]["evaluations"][0]["juggles"].size(), 3u);
}

TEST_F(EvalDashboardTest, ABadLineAnUnknownEdgeAndNoEdgeLinesAreRefusedByFileAndLine) {
  const std::string bad = testing::WriteTemp(
      "eval_bad.jsonl", std::string(kEval).substr(0, std::string(kEval).find("{\"table\":\"edge\"")) +
                            "{not json\n");
  absl::StatusOr<DashboardReport> report = RenderEvalDashboard(bad, config_);
  ASSERT_FALSE(report.ok());
  EXPECT_EQ(report.status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(std::string(report.status().message()), HasSubstr(bad + ":4: not a JSON object"));

  const std::string unknown = testing::WriteTemp(
      "eval_unknown.jsonl",
      R"({"table":"edge","from":"right_foot_down","to":"head_up","chosen":1,"completed":0,"failed":1})"
      "\n");
  report = RenderEvalDashboard(unknown, config_);
  ASSERT_FALSE(report.ok());
  EXPECT_THAT(std::string(report.status().message()),
              HasSubstr(unknown + ":1: edge right_foot_down -> head_up is not in the graph"));

  const std::string no_edges = testing::WriteTemp(
      "eval_no_edges.jsonl", std::string(kEval).substr(0, std::string(kEval).find("{\"table\":\"edge\"")));
  report = RenderEvalDashboard(no_edges, config_);
  ASSERT_FALSE(report.ok());
  EXPECT_EQ(report.status().code(), absl::StatusCode::kFailedPrecondition);
  EXPECT_THAT(std::string(report.status().message()), HasSubstr("no edge lines"));
}

}  // namespace
}  // namespace juggle

// The dashboard's state and JSON: bounded history thinned over the whole run, incremental
// history requests, per-edge and per-node walk statistics, the run-state decision, worker
// rows, and the routes serving page, files and API. The run log read back and replayed into
// the same state: learner/run_log_test.cc.
#include <cmath>
#include <cstring>
#include <fstream>
#include <regex>
#include <sstream>

#include "absl/strings/match.h"
#include "common/testing/temp_dir.h"
#include "gmock/gmock.h"
#include "gtest/gtest.h"
#include "learner/dashboard_assets.h"
#include "learner/dashboard_json.h"
#include "learner/dashboard_state.h"
#include "learner/testing/two_node_run.h"
#include "learner/http_routes.h"
#include "learner/learner_metrics.h"
#include "nlohmann/json.hpp"

namespace juggle {
namespace {

using ::testing::HasSubstr;
using Json = nlohmann::json;

runlog::IterationRecord Report(int iteration) {
  runlog::IterationRecord r;
  r.set_iteration(iteration);
  r.set_samples(iteration * 100);
  r.set_iteration_samples(100);
  r.set_iteration_s(0.5);
  r.set_mean_return(0.1 * iteration);
  r.set_policy_version(iteration);
  (*r.mutable_outcomes())["ball_lost"] = 3;
  return r;
}

// Tells `state` of one iteration with these edge events and walk counts after them.
void Tell(DashboardState* state, const runlog::IterationRecord& record,
          const std::vector<EdgeEvent>& events, const std::vector<double>& edge_counts) {
  WalkEventTotals walk;
  walk.Resize(2);
  for (const EdgeEvent& e : events) walk.Add(e);
  ASSERT_TRUE(state->OnIteration({record, walk, edge_counts}).ok());
}

TEST(DashboardStateTest, HistoryStaysBoundedAndSpansTheWholeRun) {
  DashboardState state(TwoNodeRun(), /*capacity=*/10);
  for (int i = 1; i <= 100; ++i) Tell(&state, Report(i), {}, {1.0, 2.0});
  const DashboardState::History h = state.HistorySince(0, 0);
  EXPECT_LE(h.points.size(), 10u);
  EXPECT_GE(h.points.size(), 5u);
  EXPECT_EQ(h.stride, 16);
  EXPECT_EQ(h.last_sequence, 100);
  // Evenly spread from the start to the end of the run.
  EXPECT_EQ(h.points.front().iteration(), 16);
  EXPECT_EQ(h.points.back().iteration(), 96);
  for (size_t i = 0; i < h.points.size(); ++i) EXPECT_EQ(h.sequences[i] % 16, 0);
}

TEST(DashboardStateTest, HistorySinceReturnsOnlyNewPointsWhileTheStrideIsUnchanged) {
  DashboardState state(TwoNodeRun(), 100);
  for (int i = 1; i <= 5; ++i) Tell(&state, Report(i), {}, {1.0, 2.0});
  const DashboardState::History first = state.HistorySince(0, 0);
  ASSERT_EQ(first.points.size(), 5u);
  Tell(&state, Report(6), {}, {1.0, 2.0});
  const DashboardState::History next = state.HistorySince(first.last_sequence, first.stride);
  ASSERT_EQ(next.points.size(), 1u);
  EXPECT_EQ(next.points[0].iteration(), 6);
  // A client with another stride gets everything again.
  EXPECT_EQ(state.HistorySince(first.last_sequence, 4).points.size(), 6u);
}

TEST(DashboardStateTest, CountsEdgeEventsInTotalAndOverTheRecentWindow) {
  DashboardState state(TwoNodeRun(), 100);
  const std::vector<EdgeEvent> events = {{0, EdgeEventType::kChosen},
                                         {0, EdgeEventType::kCompleted},
                                         {0, EdgeEventType::kChosen},
                                         {0, EdgeEventType::kFailed},
                                         {1, EdgeEventType::kChosen}};
  Tell(&state, Report(1), events, {1.5, 2.0});
  for (int i = 2; i <= DashboardState::kRecentIterations + 1; ++i) {
    Tell(&state, Report(i), {{1, EdgeEventType::kFailed}}, {1.5, 2.0});
  }
  const DashboardState::Snapshot s = state.Take();
  EXPECT_EQ(s.totals.chosen, (std::vector<int64_t>{2, 1}));
  EXPECT_EQ(s.totals.completed, (std::vector<int64_t>{1, 0}));
  EXPECT_EQ(s.totals.failed, (std::vector<int64_t>{1, DashboardState::kRecentIterations}));
  // The first iteration left the window.
  EXPECT_EQ(s.recent.chosen, (std::vector<int64_t>{0, 0}));
  EXPECT_EQ(s.recent.failed, (std::vector<int64_t>{0, DashboardState::kRecentIterations}));
  EXPECT_EQ(s.edge_counts, (std::vector<double>{1.5, 2.0}));
}

TEST(DashboardJsonTest, GraphShowsWeightsProbabilitiesAndPerNodeSuccess) {
  DashboardState state(TwoNodeRun(), 100);
  Tell(&state, Report(1),
       {{0, EdgeEventType::kChosen},
        {0, EdgeEventType::kCompleted},
        {0, EdgeEventType::kChosen},
        {0, EdgeEventType::kCompleted},
        {0, EdgeEventType::kChosen},
        {0, EdgeEventType::kFailed}},
       {3.0, 2.0});
  WorkerRegistry registry(1);
  Metrics metrics;
  DeclareLearnerMetrics(&metrics);
  const Json j = Json::parse(StatusJson(LiveStatus(state, registry, metrics)));
  const Json& graph = j["graph"];
  ASSERT_EQ(graph["nodes"].size(), 2u);
  EXPECT_EQ(graph["nodes"][1]["name"], "b");
  EXPECT_EQ(graph["nodes"][1]["entered"], 3);
  EXPECT_NEAR(graph["nodes"][1]["success"].get<double>(), 2.0 / 3.0, 1e-12);
  EXPECT_TRUE(graph["nodes"][0]["success"].is_null());  // nothing ended in a yet
  EXPECT_EQ(graph["edges"][0]["weight"], 3.0);
  EXPECT_EQ(graph["edges"][0]["probability"], 1.0);  // a's only edge
  EXPECT_EQ(graph["edges"][0]["chosen"], 3);
  EXPECT_EQ(j["run"]["config"], "test_run");
  EXPECT_EQ(j["progress"]["iteration"], 1);
  EXPECT_EQ(j["latest"]["outcomes"]["ball_lost"], 3);
}

// A live learner's status pieces: the two-node run's dashboard state, a registry, metrics.
class DashboardStatusTest : public ::testing::Test {
 protected:
  void SetUp() override { DeclareLearnerMetrics(&metrics); }
  Json Status() { return Json::parse(StatusJson(LiveStatus(state, registry, metrics))); }

  DashboardState state{TwoNodeRun(), 100};
  WorkerRegistry registry{1};
  Metrics metrics;
  std::optional<uint64_t> replaced;
  const WorkerRegistry::Clock::time_point now = WorkerRegistry::Clock::now();
};

TEST_F(DashboardStatusTest, StatusListsLiveWorkersAndMarksASilentOne) {
  const WorkerInfo fresh = *registry.Register(0, 8, "node-a", now, &replaced);
  const WorkerInfo silent = *registry.Register(1, 8, "node-b", now - std::chrono::seconds(5), &replaced);
  registry.CountChunk(fresh.incarnation, true);
  registry.CountChunk(fresh.incarnation, true);
  registry.CountChunk(fresh.incarnation, false);
  registry.Touch(fresh.incarnation, now, 3, 1000);
  registry.Touch(silent.incarnation, now - std::chrono::seconds(5), 3, 1000);
  const Json j = Status();
  const Json& rows = j["workers"]["rows"];
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_EQ(rows[0]["slot"], 0);
  EXPECT_EQ(rows[0]["host"], "node-a");
  EXPECT_EQ(rows[0]["chunks_accepted"], 2);
  EXPECT_EQ(rows[0]["chunks_rejected"], 1);
  EXPECT_EQ(rows[0]["status"], "ok");
  EXPECT_EQ(rows[1]["status"], "silent");
  EXPECT_GE(rows[1]["heartbeat_age_s"].get<double>(), 5.0);
  EXPECT_EQ(j["workers"]["needed"], 2);
  EXPECT_EQ(rows[0]["sessions"], 1);
}

TEST_F(DashboardStatusTest, StatusShowsAWorkersSessionsAndTheReconnectsOfEverySlot) {
  ASSERT_TRUE(registry.Register(0, 8, "node-a", now, &replaced, /*sessions_before=*/3).ok());
  metrics.Add("juggle_worker_reconnects_total", 3, {{"slot", "0"}});
  metrics.Add("juggle_worker_reconnects_total", 2, {{"slot", "1"}});
  const Json j = Status();
  EXPECT_EQ(j["workers"]["rows"][0]["sessions"], 4);
  EXPECT_EQ(j["throughput"]["reconnects"], 5);
}

TEST(RunStateTest, WaitingForWorkersWhenFewerThanTheModeNeeds) {
  RunStateInputs in;
  in.phase = LoopPhase::kWaitingForData;
  in.live_workers = 1;
  in.needed_workers = 2;
  const RunState s = DecideRunState(in);
  EXPECT_EQ(s.state, "waiting for workers");
  EXPECT_THAT(s.reason, HasSubstr("1 live worker(s)"));
}

TEST(RunStateTest, StalledNamesTheSlotsTheSynchronousIterationWaitsFor) {
  RunStateInputs in;
  in.phase = LoopPhase::kWaitingForData;
  in.live_workers = 3;
  in.needed_workers = 1;
  in.typical_iteration_s = 2;
  in.seconds_since_progress = kStallFloorSeconds + 1;
  in.version = 12;
  in.waiting_for_slots = {1, 2};
  in.queue_depth = 0;
  in.queue_capacity = 64;
  const RunState s = DecideRunState(in);
  EXPECT_EQ(s.state, "stalled");
  EXPECT_THAT(s.reason, HasSubstr("waiting for version 12 data from slot(s) 1, 2"));
  // Slow iterations raise the threshold: 10 x 20 s.
  in.typical_iteration_s = 20;
  EXPECT_EQ(DecideRunState(in).state, "training");
}

TEST(RunStateTest, EvaluatingAndFinishedAreShownAsSuch) {
  RunStateInputs in;
  in.phase = LoopPhase::kEvaluating;
  in.seconds_since_progress = 1000;  // an evaluation is not a stall
  EXPECT_EQ(DecideRunState(in).state, "evaluating");
  in.phase = LoopPhase::kFinished;
  EXPECT_EQ(DecideRunState(in).state, "finished");
}

TEST(DashboardRoutesTest, ServesThePageItsFilesTheApiAndMetrics) {
  DashboardState state(TwoNodeRun(), 100);
  WorkerRegistry registry(1);
  Metrics metrics;
  DeclareLearnerMetrics(&metrics);
  HttpServer::Handler routes = LearnerHttpRoutes(&metrics, &state, &registry);
  HttpRequest request;
  request.path = "/";
  HttpResponse page = routes(request);
  EXPECT_EQ(page.status, 200);
  EXPECT_THAT(page.content_type, HasSubstr("text/html"));
  EXPECT_THAT(page.body, HasSubstr("static/chart.min.js"));
  for (const char* file : {"/static/chart.min.js", "/static/d3.min.js", "/static/dashboard.js",
                           "/static/dashboard.css"}) {
    request.path = file;
    HttpResponse r = routes(request);
    EXPECT_EQ(r.status, 200) << file;
    EXPECT_GT(r.body.size(), 100u) << file;
    EXPECT_EQ(r.cache_control, "public, max-age=3600");
  }
  request.path = "/api/status";
  HttpResponse status = routes(request);
  EXPECT_EQ(status.content_type, "application/json");
  EXPECT_EQ(Json::parse(status.body)["state"]["state"], "starting");
  request.path = "/api/history";
  EXPECT_EQ(Json::parse(routes(request).body)["points"].size(), 0u);
  request.path = "/metrics";
  EXPECT_THAT(routes(request).body, HasSubstr("# TYPE juggle_samples_total counter"));
  request.path = "/static/../etc/passwd";
  EXPECT_EQ(routes(request).status, 404);
}

TEST(DashboardAssetsTest, TheInlinedPageHasNoExternalReferences) {
  const std::string page = InlineDashboardPage("window.JUGGLE_DATA = {\"x\": \"</script>\"};");
  EXPECT_THAT(page, ::testing::Not(HasSubstr("src=\"static/")));
  EXPECT_THAT(page, ::testing::Not(HasSubstr("href=\"static/")));
  EXPECT_THAT(page, HasSubstr("Chart.js v3"));
  EXPECT_THAT(page, HasSubstr("<\\/script>\"};"));  // the data cannot close its script early
  EXPECT_GT(page.size(), 400000u);
}

// Every metric the deployed queries name (Grafana panels, alerting and recording rules) is one
// the learner declares, and every recording rule they use is defined: a renamed metric cannot
// silently empty a panel or disable an alert.
TEST(DeployedQueriesTest, GrafanaAndRulesNameOnlyDeclaredMetricsAndDefinedRules) {
  const char* root = std::getenv("JUGGLE_SOURCE_DIR");
  const std::string dir = std::string(root ? root : ".") + "/deploy/";
  Metrics metrics;
  DeclareLearnerMetrics(&metrics);
  const std::string declared = metrics.RenderPrometheus();
  auto read = [](const std::string& path) {
    std::ifstream in(path);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
  };
  const std::string recording = read(dir + "prometheus/recording_rules.yml");
  ASSERT_FALSE(recording.empty());
  int names = 0, rules = 0;
  for (const std::string file : {"grafana/juggle.json", "prometheus/recording_rules.yml",
                                 "prometheus/alerting_rules.yml"}) {
    const std::string text = read(dir + file);
    ASSERT_FALSE(text.empty()) << file;
    const std::regex metric(R"((^|[^:a-z_])(juggle_[a-z0-9_]+))");
    for (auto it = std::sregex_iterator(text.begin(), text.end(), metric);
         it != std::sregex_iterator(); ++it) {
      std::string name = (*it)[2].str();
      for (const char* suffix : {"_bucket", "_sum", "_count"}) {
        const std::string base = name.substr(0, name.size() - std::strlen(suffix));
        if (absl::EndsWith(name, suffix) && absl::StrContains(declared, "# TYPE " + base + " histogram")) {
          name = base;
        }
      }
      EXPECT_THAT(declared, HasSubstr("# TYPE " + name + " ")) << file << " names " << name;
      ++names;
    }
    const std::regex rule(R"((instance|job):juggle_[a-z0-9_]+:[a-z0-9_]+)");
    for (auto it = std::sregex_iterator(text.begin(), text.end(), rule);
         it != std::sregex_iterator(); ++it) {
      EXPECT_THAT(recording, HasSubstr("record: " + it->str() + "\n")) << file << " uses " << it->str();
      ++rules;
    }
  }
  EXPECT_GT(names, 40);
  EXPECT_GT(rules, 10);
}

}  // namespace
}  // namespace juggle

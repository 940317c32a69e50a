// The dashboard in a real browser (Debian's `chromium`, headless, software GL): a learner and a
// worker run; the page loads, fetches its API and draws; the DOM it leaves has the worker's row,
// the control graph's nodes, numbers within a refresh of /metrics, and no JavaScript error (none
// caught by the page, none on the console). `juggle dashboard`'s file renders the same way
// offline. Screenshots go to $JUGGLE_SCREENSHOT_DIR (default: the test's scratch directory;
// docs/images/ holds committed ones). Skips only when chromium is not installed.
#include <cstdlib>
#include <fstream>
#include <memory>
#include <regex>
#include <sstream>
#include <string>

#include "common/testing/temp_dir.h"
#include "gmock/gmock.h"
#include "gtest/gtest.h"
#include "nlohmann/json.hpp"
#include "tests/service_test_util.h"

namespace juggle {
namespace {

using Json = nlohmann::json;
using ::testing::HasSubstr;
using ::testing::Not;
using testing::ChildProcess;
using testing::FindProgram;
using testing::FreePort;
using testing::ScrapeMetric;
using testing::WaitFor;

std::string ReadAll(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

int Count(const std::string& text, const std::regex& pattern) {
  return static_cast<int>(std::distance(std::sregex_iterator(text.begin(), text.end(), pattern),
                                        std::sregex_iterator()));
}

// The value of the attribute `name` on the <body> tag of a dumped DOM ("" when absent).
std::string BodyAttribute(const std::string& dom, const std::string& name) {
  std::smatch m;
  const std::regex body("<body[^>]*>");
  if (!std::regex_search(dom, m, body)) return "";
  std::smatch a;
  const std::string tag = m.str();
  if (!std::regex_search(tag, a, std::regex(name + "=\"([^\"]*)\""))) return "";
  return a[1].str();
}

class DashboardBrowserTest : public ::testing::Test {
 protected:
  void SetUp() override {
    chromium_ = FindProgram("chromium");
    if (chromium_.empty()) {
      GTEST_SKIP() << "chromium is not installed (apt-get install chromium; "
                      "scripts/dev/install_deps.sh)";
    }
    dir_ = MakeTempDir("juggle_browser_");
    const char* shots = std::getenv("JUGGLE_SCREENSHOT_DIR");
    screenshot_dir_ = shots && *shots ? shots : dir_;
  }
  void TearDown() override {
    if (dir_.empty()) return;
    if (!HasFailure() && !std::getenv("JUGGLE_KEEP_TEST_LOGS")) std::system(("rm -rf " + dir_).c_str());
    else std::fprintf(stderr, "logs kept in %s\n", dir_.c_str());
  }
  // Runs headless chromium on `url` with `extra` flags; returns its stdout (the DOM with
  // --dump-dom); its stderr (console messages) goes to <dir>/<name>.console.
  std::string Chromium(const std::string& url, const std::vector<std::string>& extra,
                       const std::string& name) {
    std::vector<std::string> args = {
        "--headless", "--no-sandbox", "--use-gl=swiftshader", "--use-angle=swiftshader",
        "--enable-unsafe-swiftshader",
        "--no-first-run", "--disable-extensions", "--hide-scrollbars",
        "--user-data-dir=" + dir_ + "/chromium-" + name, "--enable-logging=stderr", "--v=0",
        "--window-size=1400,2400", "--virtual-time-budget=9000"};
    args.insert(args.end(), extra.begin(), extra.end());
    args.push_back(url);
    std::string command = chromium_;
    for (const std::string& a : args) command += " '" + a + "'";
    command += " > '" + dir_ + "/" + name + ".out' 2> '" + dir_ + "/" + name + ".console'";
    EXPECT_EQ(std::system(command.c_str()), 0) << command;
    return ReadAll(dir_ + "/" + name + ".out");
  }
  // Console lines chromium logged for the page (console.* calls and uncaught errors).
  std::string ConsoleMessages(const std::string& name) {
    std::istringstream in(ReadAll(dir_ + "/" + name + ".console"));
    std::string line, out;
    while (std::getline(in, line)) {
      if (line.find("CONSOLE") != std::string::npos || line.find("Uncaught") != std::string::npos) {
        out += line + "\n";
      }
    }
    return out;
  }
  // Asserts what every rendering of the page must show: loaded, no error caught by the page,
  // none on the console, the graph's `nodes` drawn.
  void ExpectRendered(const std::string& dom, const std::string& name, int nodes) {
    EXPECT_EQ(BodyAttribute(dom, "data-loaded"), "1") << "the page never rendered its data";
    EXPECT_THAT(dom, HasSubstr("id=\"js-errors\" hidden")) << "the page caught a JavaScript error";
    EXPECT_EQ(ConsoleMessages(name), "") << "console messages (errors?) while loading the page";
    EXPECT_EQ(Count(dom, std::regex("<g class=\"node[ \"]")), nodes) << "graph nodes drawn";
    EXPECT_EQ(Count(dom, std::regex("<canvas id=\"chart-[a-z-]+\"[^>]*(width|style)=")), 13)
        << "every chart drew on its canvas";
  }

  std::string chromium_, dir_, screenshot_dir_;
};

TEST_F(DashboardBrowserTest, LivePageShowsTheWorkerTheGraphAndTheLearnersNumbers) {
  const int port = FreePort(), metrics_port = FreePort();
  ChildProcess learner({"learner", "--config=tests/data/tiny_right_foot.textproto",
                        "--port=" + std::to_string(port),
                        "--metrics_port=" + std::to_string(metrics_port),
                        "--run_dir=" + dir_ + "/run"},
                       dir_ + "/learner.log");
  ChildProcess worker({"worker", "--learner=127.0.0.1:" + std::to_string(port), "--envs=4",
                       "--threads=1", "--slot=0"},
                      dir_ + "/worker.log");
  ASSERT_TRUE(WaitFor([&] {
    return ScrapeMetric(metrics_port, "juggle_iterations_total").value_or(0) >= 3;
  }, 90)) << "the learner did not train 3 iterations";
  absl::StatusOr<std::string> status = HttpGet(metrics_port, "/api/status");
  ASSERT_TRUE(status.ok()) << status.status();
  const int nodes = static_cast<int>(Json::parse(*status)["graph"]["nodes"].size());
  ASSERT_GT(nodes, 1);

  const double iterations_before = *ScrapeMetric(metrics_port, "juggle_iterations_total");
  const double samples_before = *ScrapeMetric(metrics_port, "juggle_samples_total");
  const std::string url = "http://127.0.0.1:" + std::to_string(metrics_port) + "/";
  const std::string dom = Chromium(url, {"--dump-dom"}, "live");
  const double iterations_after = *ScrapeMetric(metrics_port, "juggle_iterations_total");
  const double samples_after = *ScrapeMetric(metrics_port, "juggle_samples_total");

  ExpectRendered(dom, "live", nodes);
  EXPECT_THAT(dom, HasSubstr("<figure id=\"loop-figure\" hidden")) << "no labels, no loop view";
  // The worker's row, and the numbers of one refresh between the two scrapes of /metrics.
  EXPECT_THAT(dom, HasSubstr("<tr data-slot=\"0\""));
  EXPECT_THAT(dom, Not(HasSubstr("id=\"no-workers\" class=\"muted\">")));
  const double iteration = std::stod(BodyAttribute(dom, "data-iteration"));
  const double samples = std::stod(BodyAttribute(dom, "data-samples"));
  EXPECT_GE(iteration, iterations_before);
  EXPECT_LE(iteration, iterations_after);
  EXPECT_GE(samples, samples_before);
  EXPECT_LE(samples, samples_after);
  // The state badge (a tiny run checkpoints every iteration).
  EXPECT_THAT(dom, ::testing::ContainsRegex(
                       "<span id=\"state\" class=\"badge\" data-state=\"(training|checkpointing)\">"));

  Chromium(url, {"--screenshot=" + screenshot_dir_ + "/dashboard_live.png"}, "live-shot");
  EXPECT_EQ(ReadAll(screenshot_dir_ + "/dashboard_live.png").substr(1, 3), "PNG");

  learner.Kill(SIGTERM);
  EXPECT_EQ(learner.Wait(60), 0);

  // An iteration of planner-guided training appended to the log: the loop view shows it.
  {
    std::ifstream in(dir_ + "/run/metrics.jsonl");
    std::string line, last_iteration;
    while (std::getline(in, line)) {
      if (line.rfind("{\"iteration\":", 0) == 0) last_iteration = line;  // learner/run_log.h
    }
    ASSERT_FALSE(last_iteration.empty());
    Json guided = Json::parse(last_iteration);
    guided["iteration"] = guided["iteration"].get<int>() + 1;
    guided["demo_buffer"] = 400;
    guided["imitation_fresh_error"] = 0.3;
    guided["expert_labels"] = 40;
    guided["expert_replans"] = 14;
    guided["expert_rollout_steps"] = 9000;
    guided["expert_rescues"] = 2;
    guided["expert_proposal_tried"] = 14;
    guided["expert_proposal_chosen"] = 5;
    guided["expert_proposal_weight_sum"] = 9.5;
    std::ofstream(dir_ + "/run/metrics.jsonl", std::ios::app) << guided.dump() << "\n";
  }

  // The finished run, rendered offline by `juggle dashboard` into one file.
  ChildProcess report({"dashboard", "--run_dir=" + dir_ + "/run",
                       "--out=" + dir_ + "/report.html"},
                      dir_ + "/report.log");
  ASSERT_EQ(report.Wait(60), 0) << ReadAll(dir_ + "/report.log");
  const std::string html = ReadAll(dir_ + "/report.html");
  EXPECT_THAT(html, Not(HasSubstr("src=\"static/")));
  const std::string offline = Chromium("file://" + dir_ + "/report.html", {"--dump-dom"}, "report");
  ExpectRendered(offline, "report", nodes);
  EXPECT_THAT(offline, HasSubstr("<span id=\"state\" class=\"badge\" data-state=\"recorded\">"));
  EXPECT_GE(std::stod(BodyAttribute(offline, "data-iteration")), iterations_after);
  EXPECT_THAT(offline, HasSubstr("<figure id=\"loop-figure\">")) << "the loop view of the labels";
}

TEST_F(DashboardBrowserTest, AnEvaluationsPageShowsItsSummaryAndTheGraphByItsNodeTable) {
  // Zero action on the right foot: every episode completes its DOWN node and fails in its UP
  // node, so the node table's success is 100 % and 0 %.
  ChildProcess eval({"eval", "--controller=zero", "--config=configs/right_foot.textproto",
                     "--episodes=3", "--max_seconds=10", "--json=" + dir_ + "/eval.jsonl"},
                    dir_ + "/eval.log");
  ASSERT_EQ(eval.Wait(120), 0) << ReadAll(dir_ + "/eval.log");
  EXPECT_THAT(ReadAll(dir_ + "/eval.jsonl"), HasSubstr("\"table\":\"edge\""));
  ChildProcess report({"dashboard", "--eval=" + dir_ + "/eval.jsonl",
                       "--config=configs/right_foot.textproto", "--out=" + dir_ + "/eval.html"},
                      dir_ + "/eval_report.log");
  ASSERT_EQ(report.Wait(60), 0) << ReadAll(dir_ + "/eval_report.log");
  const std::string dom = Chromium("file://" + dir_ + "/eval.html", {"--dump-dom"}, "eval");
  EXPECT_EQ(BodyAttribute(dom, "data-loaded"), "1") << "the page never rendered its data";
  EXPECT_EQ(BodyAttribute(dom, "data-kind"), "evaluation");
  EXPECT_THAT(dom, HasSubstr("id=\"js-errors\" hidden")) << "the page caught a JavaScript error";
  EXPECT_EQ(ConsoleMessages("eval"), "");
  EXPECT_THAT(dom, HasSubstr("<section id=\"evaluation-section\">")) << "shown, not hidden";
  EXPECT_THAT(dom, HasSubstr("<dd id=\"eval-episodes\">3</dd>"));
  EXPECT_EQ(Count(dom, std::regex("<g class=\"node[ \"]")), 2) << "graph nodes drawn";
  EXPECT_EQ(Count(dom, std::regex("data-name=\"right_foot_down\"[^]*?<text class=\"rate\"[^>]*>100 %</text>")), 1);
  EXPECT_EQ(Count(dom, std::regex("data-name=\"right_foot_up\"[^]*?<text class=\"rate\"[^>]*>0 %</text>")), 1);
  Chromium("file://" + dir_ + "/eval.html", {"--screenshot=" + screenshot_dir_ + "/dashboard_eval.png"},
           "eval_shot");
}

}  // namespace
}  // namespace juggle

// A real Prometheus (Debian's `prometheus`, started in the background and stopped by PID)
// scraping a real learner with one worker, loaded with deploy/prometheus' rules: through
// Prometheus' HTTP API, the learner's series arrive with the scrape job's labels, a recording
// rule evaluates to a positive rate, every rule group is healthy, and when the worker is killed
// the JuggleNoWorkers alert becomes pending. Skips only when the prometheus binary is missing.
#include <cctype>
#include <cstdlib>
#include <fstream>
#include <memory>
#include <string>

#include "common/testing/temp_dir.h"
#include "gmock/gmock.h"
#include "gtest/gtest.h"
#include "nlohmann/json.hpp"
#include "tests/service_test_util.h"

namespace juggle {
namespace {

using Json = nlohmann::json;
using testing::ChildProcess;
using testing::FindProgram;
using testing::FreePort;
using testing::ScrapeMetric;
using testing::WaitFor;

std::string UrlEncode(const std::string& s) {
  static const char kHex[] = "0123456789ABCDEF";
  std::string out;
  for (unsigned char c : s) {
    if (std::isalnum(c) || c == '-' || c == '_' || c == '.' || c == '~') {
      out += static_cast<char>(c);
    } else {
      out += '%';
      out += kHex[c >> 4];
      out += kHex[c & 15];
    }
  }
  return out;
}

class PrometheusScrapeTest : public ::testing::Test {
 protected:
  void SetUp() override {
    prometheus_ = FindProgram("prometheus");
    if (prometheus_.empty()) {
      GTEST_SKIP() << "prometheus is not installed (apt-get install prometheus; "
                      "scripts/dev/install_deps.sh)";
    }
    dir_ = MakeTempDir("juggle_prom_");
  }
  void TearDown() override {
    if (dir_.empty()) return;
    if (!HasFailure() && !std::getenv("JUGGLE_KEEP_TEST_LOGS")) std::system(("rm -rf " + dir_).c_str());
    else std::fprintf(stderr, "logs kept in %s\n", dir_.c_str());
  }
  // The `data.result` array of an instant query; empty when Prometheus does not answer.
  Json Query(const std::string& promql) {
    absl::StatusOr<std::string> body =
        HttpGet(prometheus_port_, "/api/v1/query?query=" + UrlEncode(promql));
    if (!body.ok()) return Json::array();
    Json j = Json::parse(*body, nullptr, false);
    if (j.is_discarded() || j.value("status", "") != "success") return Json::array();
    return j["data"]["result"];
  }

  std::string prometheus_, dir_;
  int prometheus_port_ = 0;
};

TEST_F(PrometheusScrapeTest, ScrapesTheLearnerEvaluatesTheRulesAndRaisesTheNoWorkersAlert) {
  const int port = FreePort(), metrics_port = FreePort();
  prometheus_port_ = FreePort();
  ChildProcess learner({"learner", "--config=tests/data/tiny_right_foot.textproto",
                        "--port=" + std::to_string(port),
                        "--metrics_port=" + std::to_string(metrics_port),
                        "--run_dir=" + dir_ + "/run"},
                       dir_ + "/learner.log");
  auto worker = std::make_unique<ChildProcess>(
      std::vector<std::string>{"worker", "--learner=127.0.0.1:" + std::to_string(port),
                               "--envs=4", "--threads=1", "--slot=0"},
      dir_ + "/worker.log");
  ASSERT_TRUE(WaitFor([&] { return ScrapeMetric(metrics_port, "juggle_workers_connected") == 1; },
                      60))
      << "the worker did not register";

  // deploy/prometheus' rules with a 1 s scrape and evaluation interval, aimed at this learner.
  const std::string source = std::getenv("JUGGLE_SOURCE_DIR") ? std::getenv("JUGGLE_SOURCE_DIR") : ".";
  {
    std::ofstream config(dir_ + "/prometheus.yml");
    config << "global:\n  scrape_interval: 1s\n  evaluation_interval: 1s\n"
           << "rule_files:\n  - " << source << "/deploy/prometheus/recording_rules.yml\n"
           << "  - " << source << "/deploy/prometheus/alerting_rules.yml\n"
           << "scrape_configs:\n  - job_name: juggle-learner\n    static_configs:\n"
           << "      - targets: [\"127.0.0.1:" << metrics_port << "\"]\n";
  }
  ChildProcess prometheus(prometheus_,
                          {"--config.file=" + dir_ + "/prometheus.yml",
                           "--storage.tsdb.path=" + dir_ + "/tsdb",
                           "--web.listen-address=127.0.0.1:" + std::to_string(prometheus_port_),
                           "--log.level=warn"},
                          dir_ + "/prometheus.log");
  ASSERT_TRUE(WaitFor([&] { return HttpGet(prometheus_port_, "/-/ready").ok(); }, 60))
      << "prometheus did not become ready; see " << dir_ << "/prometheus.log";

  // A series arrives, with the scrape's labels, and keeps up with the learner.
  ASSERT_TRUE(WaitFor([&] { return Query("juggle_policy_version >= 1").size() == 1; }, 90))
      << "no juggle_policy_version >= 1 in Prometheus";
  const Json version = Query("juggle_policy_version")[0];
  EXPECT_EQ(version["metric"]["job"], "juggle-learner");
  EXPECT_EQ(version["metric"]["instance"], "127.0.0.1:" + std::to_string(metrics_port));
  EXPECT_EQ(Query("up{job=\"juggle-learner\"}")[0]["value"][1], "1");

  // A recording rule evaluates: trained samples per second over the scrapes so far.
  ASSERT_TRUE(WaitFor([&] { return Query("instance:juggle_samples:rate5m > 0").size() == 1; }, 60))
      << "instance:juggle_samples:rate5m never became positive";
  absl::StatusOr<std::string> rules = HttpGet(prometheus_port_, "/api/v1/rules");
  ASSERT_TRUE(rules.ok()) << rules.status();
  const Json groups = Json::parse(*rules)["data"]["groups"];
  ASSERT_EQ(groups.size(), 2u);
  for (const Json& group : groups) {
    for (const Json& rule : group["rules"]) {
      EXPECT_EQ(rule["health"], "ok") << rule["name"] << ": " << rule.value("lastError", "");
    }
  }
  EXPECT_TRUE(Query("ALERTS{alertname=\"JuggleNoWorkers\"}").empty());

  // The worker dies: the learner forgets it after worker_timeout_s (3 s) and the alert is
  // pending (it fires after 2 minutes).
  worker->Kill(SIGKILL);
  worker->Wait(5);
  ASSERT_TRUE(WaitFor([&] {
    return Query("ALERTS{alertname=\"JuggleNoWorkers\",alertstate=\"pending\"}").size() == 1;
  }, 60)) << "JuggleNoWorkers did not become pending";

  prometheus.Kill(SIGTERM);
  EXPECT_EQ(prometheus.Wait(30), 0);
  learner.Kill(SIGTERM);
  EXPECT_EQ(learner.Wait(60), 0);
}

}  // namespace
}  // namespace juggle

// Asynchronous mode end to end in one process (learner + two worker threads over loopback):
// data up to max_policy_lag versions old is trained on; older data is refused and counted.
#include <atomic>
#include <cstdlib>
#include <thread>
#include <vector>

#include "absl/strings/str_cat.h"
#include "common/testing/temp_dir.h"
#include "envs/registry.h"
#include "gtest/gtest.h"
#include "learner/learner_server.h"
#include "learner/testing/recording_observer.h"
#include "worker/worker_client.h"

namespace juggle {
namespace {

struct AsyncRun {
  double max_lag_seen = 0;
  int64_t iterations = 0;
  double stale_rejections = 0;
};

AsyncRun RunAsync(int max_policy_lag, int iterations) {
  absl::StatusOr<LoadedConfig> config = LoadRunConfig("tests/data/tiny_right_foot.textproto");
  EXPECT_TRUE(config.ok()) << config.status();
  config::ServiceConfig* svc = config->run.mutable_service();
  svc->set_synchronous(false);
  svc->set_max_policy_lag(max_policy_lag);
  svc->set_unrolls_per_iteration(4);  // one worker's contribution: train as soon as one arrives
  const std::string dir = MakeTempDir("juggle_async_");
  LearnerOptions o;
  o.config = *config;
  o.run_dir = dir;
  o.port = 0;
  o.metrics_port = -1;
  o.listen_all_interfaces = false;
  o.max_iterations = iterations;
  AsyncRun result;
  RecordingObserver recorded;
  o.observers.push_back(&recorded);
  auto server = LearnerServer::Start(std::move(o));
  EXPECT_TRUE(server.ok()) << server.status();
  std::atomic<bool> stop{false}, workers_stop{false};
  std::vector<std::thread> workers;
  for (int w = 0; w < 2; ++w) {
    workers.emplace_back([&, w] {
      WorkerOptions wo;
      wo.learner_address = absl::StrCat("127.0.0.1:", (*server)->port());
      wo.num_envs = 4;
      wo.num_threads = 1;
      wo.requested_slot = w;
      wo.stop = &workers_stop;
      wo.verbose = false;
      RunWorker(wo).IgnoreError();
    });
  }
  EXPECT_TRUE((*server)->Train(&stop).ok());
  for (const runlog::IterationRecord& r : recorded.iterations) {
    result.max_lag_seen = std::max(result.max_lag_seen, r.policy_lag());
    result.iterations = r.iteration();
  }
  result.stale_rejections =
      (*server)->metrics().Get("juggle_chunks_rejected_total", {{"reason", "stale_version"}});
  workers_stop = true;
  for (std::thread& t : workers) t.join();
  (*server)->Shutdown();
  std::system(("rm -rf " + dir).c_str());
  return result;
}

TEST(AsyncModeTest, TrainsOnDataUpToTheAllowedLag) {
  const AsyncRun run = RunAsync(/*max_policy_lag=*/3, /*iterations=*/12);
  EXPECT_EQ(run.iterations, 12);
  // Two workers and one contribution per iteration: the slower one's data is one version old.
  EXPECT_GT(run.max_lag_seen, 0.0);
  EXPECT_LE(run.max_lag_seen, 3.0);
}

TEST(AsyncModeTest, RefusesAndCountsDataOlderThanTheLag) {
  const AsyncRun run = RunAsync(/*max_policy_lag=*/0, /*iterations=*/10);
  EXPECT_EQ(run.iterations, 10);
  EXPECT_EQ(run.max_lag_seen, 0.0);
  EXPECT_GT(run.stale_rejections, 0.0);
}

}  // namespace
}  // namespace juggle

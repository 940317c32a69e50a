// A connection that stalls silently (a middlebox that drops its state, a hung peer: the proxy
// stops forwarding both ways and answers new connections never) is detected by the worker's
// keepalive within keepalive_time + keepalive_timeout, and the worker reconnects and
// contributes again once the path heals. Without keepalive (gRPC's default) the same stall is
// never noticed: the control case that shows the test can fail. Real processes (`juggle
// learner`, `juggle worker`) on loopback through the fault proxy; no namespaces needed.
#include <chrono>
#include <cstdlib>
#include <string>

#include "common/testing/temp_dir.h"
#include "gtest/gtest.h"
#include "tests/netfaults/fault_proxy.h"
#include "tests/netfaults/learner_behind_proxy.h"
#include "tests/netfaults/netfaults_util.h"
#include "tests/service_test_util.h"

namespace juggle::netfaults {
namespace {

using testing::ChildProcess;
using testing::WaitFor;

constexpr double kKeepaliveTime = 2, kKeepaliveTimeout = 2;

class StallDetectionTest : public LearnerBehindProxyTest {
 protected:
  StallDetectionTest() : LearnerBehindProxyTest("juggle_stall_") {}
  void StartWorker(double keepalive_time) {
    worker_ = std::make_unique<ChildProcess>(
        std::vector<std::string>{"worker", LearnerFlag(),
                                 "--envs=4", "--threads=1", "--slot=0",
                                 "--keepalive_time=" + std::to_string(keepalive_time),
                                 "--keepalive_timeout=" + std::to_string(kKeepaliveTimeout),
                                 "--max_reconnect_backoff=2", "--min_connect_timeout=2"},
        dir_ + "/worker.log");
  }
  double Accepted() { return ScrapeAccounts(metrics_port_).accepted; }
  // Stops forwarding on the open connection both ways; new connections are accepted and
  // never answered.
  void Stall() {
    Faults f;
    f.upstream.paused = f.downstream.paused = true;
    f.stall_new = true;
    proxy_->SetFaults(f);
  }
};

TEST_F(StallDetectionTest, AStalledConnectionIsDetectedWithinKeepaliveTimePlusTimeout) {
  StartWorker(kKeepaliveTime);
  ASSERT_TRUE(WaitFor([&] { return Accepted() > 0; }, 90)) << "the worker never contributed";
  const int64_t connections = proxy_->stats().accepted;
  Stall();
  const auto stalled_at = Clock::now();
  // The worker's next connection attempt is the sign that it gave the stalled one up.
  ASSERT_TRUE(WaitFor([&] { return proxy_->stats().accepted > connections; }, 30))
      << "the stalled connection was not detected in 30 s";
  const double detected_s = Since(stalled_at);
  std::printf("stall detected after %.2f s (keepalive %.0f s + timeout %.0f s)\n", detected_s,
              kKeepaliveTime, kKeepaliveTimeout);
  // keepalive_time + keepalive_timeout, plus the worker's first reconnect backoff (0.1 s) and
  // scheduling slack.
  EXPECT_LE(detected_s, kKeepaliveTime + kKeepaliveTimeout + 1.5);

  proxy_->SetFaults(Faults());
  const double before = Accepted();
  const auto healed_at = Clock::now();
  ASSERT_TRUE(WaitFor([&] { return Accepted() > before; }, 30))
      << "the worker did not contribute again after the heal";
  std::printf("contributing again %.2f s after the heal\n", Since(healed_at));
  // A stalled reconnect attempt is abandoned after min_connect_timeout (2 s), the next comes
  // within max_reconnect_backoff (2 s), then registration, the snapshot and one contribution.
  EXPECT_LE(Since(healed_at), 15);
}

TEST_F(StallDetectionTest, WithoutKeepaliveAStalledConnectionIsNeverDetected) {
  StartWorker(/*keepalive_time=*/0);
  ASSERT_TRUE(WaitFor([&] { return Accepted() > 0; }, 90)) << "the worker never contributed";
  const int64_t connections = proxy_->stats().accepted;
  Stall();
  // Three times the bound the keepalive test holds the worker to.
  const double wait_s = 3 * (kKeepaliveTime + kKeepaliveTimeout + 1.5);
  EXPECT_FALSE(WaitFor([&] { return proxy_->stats().accepted > connections; }, wait_s))
      << "the worker noticed the stall without keepalive: the keepalive test proves nothing";
  worker_->Kill(SIGKILL);  // it waits on the stalled stream and would not see a SIGTERM soon
}

}  // namespace
}  // namespace juggle::netfaults

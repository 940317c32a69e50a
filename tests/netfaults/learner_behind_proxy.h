// The fixture of the loopback network-fault tests: a real `juggle learner` (the asynchronous
// netfaults config) with its own run folder, reached through a FaultProxy (seed 47) on
// 127.0.0.1, and room for one `juggle worker` that the test starts through the proxy. TearDown
// stops both and removes the folder unless the test failed or JUGGLE_KEEP_TEST_LOGS is set.
#ifndef JUGGLE_TESTS_NETFAULTS_LEARNER_BEHIND_PROXY_H_
#define JUGGLE_TESTS_NETFAULTS_LEARNER_BEHIND_PROXY_H_

#include <signal.h>

#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>
#include <vector>

#include "common/testing/temp_dir.h"
#include "gtest/gtest.h"
#include "tests/netfaults/fault_proxy.h"
#include "tests/netfaults/netfaults_util.h"
#include "tests/service_test_util.h"

namespace juggle::netfaults {

class LearnerBehindProxyTest : public ::testing::Test {
 protected:
  // `dir_prefix`: the run folder's name prefix (which test left it).
  explicit LearnerBehindProxyTest(std::string dir_prefix) : dir_prefix_(std::move(dir_prefix)) {}

  void SetUp() override {
    dir_ = MakeTempDir(dir_prefix_);
    port_ = testing::FreePort();
    metrics_port_ = testing::FreePort();
    learner_ = std::make_unique<testing::ChildProcess>(
        std::vector<std::string>{"learner", "--config=tests/netfaults/netfaults_async.textproto",
                                 "--port=" + std::to_string(port_),
                                 "--metrics_port=" + std::to_string(metrics_port_),
                                 "--run_dir=" + dir_ + "/run"},
        dir_ + "/learner.log");
    auto proxy = FaultProxy::Start("127.0.0.1", 0, "127.0.0.1", port_, /*seed=*/47);
    ASSERT_TRUE(proxy.ok()) << proxy.status();
    proxy_ = std::move(*proxy);
  }
  void TearDown() override {
    if (worker_) worker_->Kill(SIGTERM), worker_->Wait(20);
    learner_->Kill(SIGTERM);
    learner_->Wait(30);
    if (!HasFailure() && !std::getenv("JUGGLE_KEEP_TEST_LOGS")) {
      std::system(("rm -rf " + dir_).c_str());
    } else {
      std::fprintf(stderr, "logs kept in %s\n", dir_.c_str());
    }
  }
  // The worker's --learner flag: through the proxy.
  std::string LearnerFlag() const { return "--learner=127.0.0.1:" + std::to_string(proxy_->port()); }

  std::string dir_prefix_;
  std::string dir_;
  int port_ = 0, metrics_port_ = 0;
  std::unique_ptr<testing::ChildProcess> learner_, worker_;
  std::unique_ptr<FaultProxy> proxy_;
};

}  // namespace juggle::netfaults

#endif  // JUGGLE_TESTS_NETFAULTS_LEARNER_BEHIND_PROXY_H_

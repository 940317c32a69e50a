// common/connection_settings: out-of-range keepalive and reconnect settings are refused naming
// the flag; the channel arguments a worker gets carry keepalive on with unlimited pings.
#include "common/connection_settings.h"

#include <map>
#include <string>

#include <grpc/grpc.h>

#include "gmock/gmock.h"
#include "gtest/gtest.h"

namespace juggle {
namespace {

using ::testing::HasSubstr;

std::map<std::string, int> IntArgs(const grpc::ChannelArguments& args) {
  grpc_channel_args raw;
  args.SetChannelArgs(&raw);
  std::map<std::string, int> out;
  for (size_t i = 0; i < raw.num_args; ++i) {
    if (raw.args[i].type == GRPC_ARG_INTEGER) out[raw.args[i].key] = raw.args[i].value.integer;
  }
  return out;
}

TEST(ConnectionSettingsTest, DefaultsAreValidOnBothSides) {
  EXPECT_TRUE(Validate(WorkerConnectionSettings{}).ok());
  EXPECT_TRUE(Validate(LearnerConnectionSettings{}).ok());
}

TEST(ConnectionSettingsTest, DefaultWorkerPingsAreAllowedByTheDefaultLearner) {
  EXPECT_GE(WorkerConnectionSettings{}.keepalive_time_s,
            LearnerConnectionSettings{}.min_worker_ping_interval_s);
}

TEST(ConnectionSettingsTest, OutOfRangeValuesNameTheirFlag) {
  WorkerConnectionSettings w;
  w.keepalive_time_s = 0.1;
  EXPECT_THAT(std::string(Validate(w).message()), HasSubstr("--keepalive_time=0.1"));
  EXPECT_EQ(Validate(w).code(), absl::StatusCode::kInvalidArgument);
  w = {};
  w.keepalive_timeout_s = std::nan("");
  EXPECT_THAT(std::string(Validate(w).message()), HasSubstr("--keepalive_timeout"));
  w = {};
  w.max_reconnect_backoff_s = 0.05;  // below the initial 0.1 s
  EXPECT_THAT(std::string(Validate(w).message()), HasSubstr("--max_reconnect_backoff=0.05"));
  w = {};
  w.min_connect_timeout_s = 0;
  EXPECT_THAT(std::string(Validate(w).message()), HasSubstr("--min_connect_timeout"));
  LearnerConnectionSettings l;
  l.min_worker_ping_interval_s = -1;
  EXPECT_THAT(std::string(Validate(l).message()), HasSubstr("--min_worker_ping_interval"));
}

TEST(ConnectionSettingsTest, ZeroKeepaliveTimeTurnsKeepaliveOff) {
  WorkerConnectionSettings w;
  w.keepalive_time_s = 0;
  ASSERT_TRUE(Validate(w).ok());
  grpc::ChannelArguments args;
  ApplyTo(w, &args);
  EXPECT_EQ(IntArgs(args).count(GRPC_ARG_KEEPALIVE_TIME_MS), 0u);
}

TEST(ConnectionSettingsTest, WorkerChannelArgumentsCarryKeepaliveAndBackoff) {
  WorkerConnectionSettings w;
  w.keepalive_time_s = 2;
  w.keepalive_timeout_s = 1.5;
  w.max_reconnect_backoff_s = 3;
  w.min_connect_timeout_s = 4;
  grpc::ChannelArguments args;
  ApplyTo(w, &args);
  const std::map<std::string, int> got = IntArgs(args);
  EXPECT_EQ(got.at(GRPC_ARG_KEEPALIVE_TIME_MS), 2000);
  EXPECT_EQ(got.at(GRPC_ARG_KEEPALIVE_TIMEOUT_MS), 1500);
  EXPECT_EQ(got.at(GRPC_ARG_KEEPALIVE_PERMIT_WITHOUT_CALLS), 1);
  EXPECT_EQ(got.at(GRPC_ARG_HTTP2_MAX_PINGS_WITHOUT_DATA), 0);  // pings never stop
  EXPECT_EQ(got.at(GRPC_ARG_MAX_RECONNECT_BACKOFF_MS), 3000);
  EXPECT_EQ(got.at(GRPC_ARG_MIN_RECONNECT_BACKOFF_MS), 4000);  // gRPC's min connect timeout
}

}  // namespace
}  // namespace juggle

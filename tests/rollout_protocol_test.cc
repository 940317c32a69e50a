// The rollout protocol against a real in-process learner (configs/right_foot.textproto) over
// loopback gRPC, driven by a raw stub instead of the worker client: registration, policy
// download, chunks rejected with the documented ack codes and counted in /metrics by reason,
// and a valid contribution still trained on afterwards. Also the gRPC health service.
#include <stdlib.h>
#include <sys/stat.h>

#include <atomic>
#include <chrono>
#include <cstdlib>
#include <functional>
#include <future>
#include <limits>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include <grpcpp/generic/generic_stub.h>
#include <grpcpp/grpcpp.h>

#include "absl/strings/str_cat.h"
#include "common/chunk_codec.h"
#include "envs/registry.h"
#include "common/flat_parameters.h"
#include "common/http_server.h"
#include "envs/soccer_juggle/spec.h"
#include "gmock/gmock.h"
#include "google/protobuf/text_format.h"
#include "google/protobuf/unknown_field_set.h"
#include "common/testing/temp_dir.h"
#include "gtest/gtest.h"
#include "learner/learner_server.h"
#include "proto/rollout.grpc.pb.h"

namespace juggle {
namespace {

using soccer_juggle::kNumActions;
using soccer_juggle::ObservationSize;

using ::testing::HasSubstr;
using ::testing::Not;
using Clock = std::chrono::steady_clock;

constexpr int kNodes = 2;                         // configs/graphs/right_foot.textproto
constexpr int kObsDim = ObservationSize(kNodes);  // 94
constexpr int kInvalidArgument = 3;               // google.rpc.Code numbering
constexpr int kFailedPrecondition = 9;

// Polls `predicate` every 50 ms for up to `seconds`.
bool WaitUntil(const std::function<bool()>& predicate, double seconds) {
  const auto until = Clock::now() + std::chrono::milliseconds(int(seconds * 1000));
  while (Clock::now() < until) {
    if (predicate()) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  return predicate();
}

void SetDeadline(grpc::ClientContext* ctx, int seconds = 10) {
  ctx->set_deadline(std::chrono::system_clock::now() + std::chrono::seconds(seconds));
}

// One well-formed contribution for the right-foot learner: `num_unrolls` unrolls of
// `unroll_length` steps with finite data, nodes alternating 0/1, one truncated step.
Contribution ValidContribution(int num_unrolls, int unroll_length, int64_t version) {
  Contribution c;
  UnrollBatch& b = c.batch;
  b.num_unrolls = num_unrolls;
  b.unroll_length = unroll_length;
  b.obs_dim = kObsDim;
  b.act_dim = kNumActions;
  const size_t n = size_t(num_unrolls) * unroll_length;
  b.obs.resize(n * kObsDim);
  for (size_t i = 0; i < b.obs.size(); ++i) b.obs[i] = 0.01f * float(i % 97) - 0.5f;
  b.actions.assign(n * kNumActions, 0.05f);
  b.log_probs.assign(n, -10.0f);
  b.rewards.assign(n, 0.25f);
  b.done.assign(n, 0);
  b.truncated.assign(n, 0);
  b.truncated[unroll_length / 2] = 1;
  b.truncated_obs.assign(kObsDim, 0.1f);
  b.bootstrap_obs.assign(size_t(num_unrolls) * kObsDim, 0.2f);
  b.policy_version.assign(num_unrolls, version);
  c.node.resize(n);
  for (size_t i = 0; i < n; ++i) c.node[i] = static_cast<int32_t>(i % kNodes);
  c.events = {{0, EdgeEventType::kChosen}, {0, EdgeEventType::kCompleted}};
  c.stats.episodes = 1;
  c.stats.return_sum = 3.5;
  c.stats.length_sum = unroll_length / 2 + 1;
  c.stats.outcomes = {0, 1};
  return c;
}

class RolloutProtocolTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = MakeTempDir("juggle_protocol_");
    ASSERT_FALSE(dir_.empty());
    absl::StatusOr<LoadedConfig> config = LoadRunConfig("configs/right_foot.textproto");
    ASSERT_TRUE(config.ok()) << config.status();
    ASSERT_TRUE(config->run.service().synchronous()) << "these tests assume synchronous mode";
    // One libtorch thread: on a shared 2-core machine OpenMP spin-waiting with the config's
    // two threads makes the network's orthogonal init and the update take seconds.
    config->run.mutable_ppo()->set_torch_threads(1);
    // Small limits, to reach them: 4 workers per host, 8 in total, 64 envs each; a round
    // goes on without silent workers after 2 s.
    config::ServiceConfig* service = config->run.mutable_service();
    service->set_max_workers(8);
    service->set_max_workers_per_host(4);
    service->set_max_envs_per_worker(64);
    service->set_sync_round_timeout_s(2);
    LearnerOptions options;
    options.config = *std::move(config);
    // LearnerServer does not create its run directory (`juggle learner` does, before Start).
    options.run_dir = dir_ + "/run";
    ASSERT_EQ(::mkdir(options.run_dir.c_str(), 0755), 0);
    options.port = 0;
    options.metrics_port = LearnerOptions::kAnyFreePort;
    options.listen_all_interfaces = false;
    absl::StatusOr<std::unique_ptr<LearnerServer>> server = LearnerServer::Start(std::move(options));
    ASSERT_TRUE(server.ok()) << server.status();
    server_ = *std::move(server);
    ASSERT_GT(server_->port(), 0);
    ASSERT_GT(server_->metrics_port(), 0);
    train_thread_ = std::thread([this] { train_status_ = server_->Train(&stop_); });
    channel_ = grpc::CreateChannel(absl::StrCat("127.0.0.1:", server_->port()),
                                   grpc::InsecureChannelCredentials());
    stub_ = rpc::Rollout::NewStub(channel_);
  }

  void TearDown() override {
    stop_ = true;
    if (train_thread_.joinable()) train_thread_.join();
    if (server_) {
      server_->Shutdown();
      EXPECT_TRUE(train_status_.ok()) << train_status_;
    }
    if (!dir_.empty()) std::system(("rm -rf " + dir_).c_str());
  }

  rpc::RegisterResponse Register(int num_envs = 1, const std::string& host = "protocol-test") {
    rpc::RegisterResponse resp;
    const grpc::Status s = TryRegister(-1, num_envs, host, &resp);
    EXPECT_TRUE(s.ok()) << s.error_message();
    return resp;
  }
  grpc::Status TryRegister(int slot, int num_envs, const std::string& host,
                           rpc::RegisterResponse* resp) {
    grpc::ClientContext ctx;
    SetDeadline(&ctx);
    rpc::RegisterRequest req;
    req.set_requested_slot(slot);
    req.set_num_envs(num_envs);
    req.set_hostname(host);
    return stub_->Register(&ctx, req, resp);
  }

  // GetPolicy reassembled: version, edge counts, params bytes; or the RPC's status.
  struct Policy {
    grpc::Status status;
    int64_t version = -1;
    int64_t total_bytes = -1;
    std::vector<double> edge_counts;
    std::string params;
  };
  Policy GetPolicy(uint64_t incarnation, int64_t min_version) {
    grpc::ClientContext ctx;
    SetDeadline(&ctx);
    rpc::PolicyRequest req;
    req.set_incarnation(incarnation);
    req.set_min_version(min_version);
    std::unique_ptr<grpc::ClientReader<rpc::PolicyChunk>> reader = stub_->GetPolicy(&ctx, req);
    Policy p;
    rpc::PolicyChunk chunk;
    bool first = true;
    while (reader->Read(&chunk)) {
      if (first) {
        p.version = chunk.version();
        p.total_bytes = chunk.total_bytes();
        p.edge_counts.assign(chunk.edge_counts().begin(), chunk.edge_counts().end());
        first = false;
      }
      p.params += chunk.data();
    }
    p.status = reader->Finish();
    return p;
  }

  // The single chunk of a valid one-unroll contribution for `reg`'s incarnation.
  rpc::TrajectoryChunk ValidChunk(const rpc::RegisterResponse& reg, int64_t sequence) {
    const std::vector<rpc::TrajectoryChunk> chunks = EncodeContribution(
        ValidContribution(1, reg.unroll_length(), 0), reg.incarnation(), sequence, size_t(4) << 20);
    EXPECT_EQ(chunks.size(), 1u);
    return chunks.at(0);
  }

  std::string Metrics() {
    absl::StatusOr<std::string> body = HttpGet(server_->metrics_port(), "/metrics");
    EXPECT_TRUE(body.ok()) << body.status();
    return body.ok() ? *body : "";
  }

  std::string dir_;
  std::unique_ptr<LearnerServer> server_;
  std::atomic<bool> stop_{false};
  absl::Status train_status_;
  std::thread train_thread_;
  std::shared_ptr<grpc::Channel> channel_;
  std::unique_ptr<rpc::Rollout::Stub> stub_;
};

TEST_F(RolloutProtocolTest, RegisterReturnsSlotIncarnationConfigAndModel) {
  const rpc::RegisterResponse first = Register();
  EXPECT_EQ(first.slot(), 0);
  EXPECT_NE(first.incarnation(), 0u);
  EXPECT_FALSE(first.model_mjb().empty());
  EXPECT_TRUE(first.synchronous());
  EXPECT_EQ(first.unroll_length(), 100);  // the schema's default; right_foot sets none
  ASSERT_FALSE(first.run_config().empty());
  config::RunConfig run;
  ASSERT_TRUE(google::protobuf::TextFormat::ParseFromString(first.run_config(), &run));
  EXPECT_EQ(run.name(), "right_foot");
  EXPECT_FALSE(run.soccer_juggle().has_graph_file()) << "workers have no files: the graph travels inline";
  EXPECT_EQ(run.soccer_juggle().graph().node_size(), kNodes);

  const rpc::RegisterResponse second = Register();
  EXPECT_EQ(second.slot(), 1);
  EXPECT_NE(second.incarnation(), first.incarnation());
}

TEST_F(RolloutProtocolTest, GetPolicyReturnsTheCurrentSnapshotThatDeserializes) {
  const rpc::RegisterResponse reg = Register();
  const Policy p = GetPolicy(reg.incarnation(), -1);
  ASSERT_TRUE(p.status.ok()) << p.status.error_message();
  EXPECT_EQ(p.version, 0);
  EXPECT_EQ(p.total_bytes, static_cast<int64_t>(p.params.size()));
  EXPECT_EQ(p.edge_counts.size(), 2u);  // the right-foot graph's two edges
  absl::StatusOr<FlatParameters> params = FlatParameters::Deserialize(p.params);
  ASSERT_TRUE(params.ok()) << params.status();
  EXPECT_EQ(params->version(), 0);
  EXPECT_FALSE(params->layout().empty());
  EXPECT_FALSE(params->values().empty());
}

TEST_F(RolloutProtocolTest, GetPolicyForAnUnregisteredIncarnationFailsWithFailedPrecondition) {
  const rpc::RegisterResponse reg = Register();
  const Policy p = GetPolicy(reg.incarnation() + 1000, -1);
  EXPECT_EQ(p.status.error_code(), grpc::StatusCode::FAILED_PRECONDITION);
  EXPECT_THAT(p.status.error_message(),
              HasSubstr(absl::StrCat("unregistered incarnation ", reg.incarnation() + 1000)));
  EXPECT_TRUE(p.params.empty());
}

TEST_F(RolloutProtocolTest, RejectsBadChunksWithTheirCodesCountsThemAndStillTrains) {
  const rpc::RegisterResponse reg = Register();
  ASSERT_GT(reg.unroll_length(), 0);
  grpc::ClientContext ctx;
  SetDeadline(&ctx, 30);
  std::unique_ptr<grpc::ClientReaderWriter<rpc::TrajectoryChunk, rpc::ChunkAck>> stream =
      stub_->StreamTrajectories(&ctx);
  auto send = [&](const rpc::TrajectoryChunk& chunk) {
    rpc::ChunkAck ack;
    EXPECT_TRUE(stream->Write(chunk));
    EXPECT_TRUE(stream->Read(&ack));
    return ack;
  };
  struct Case {
    const char* name;
    std::function<void(rpc::TrajectoryChunk*)> corrupt;
    int code;
    std::string message;
  };
  const std::vector<Case> cases = {
      {"obs of a 3-node graph",
       [](rpc::TrajectoryChunk* c) {
         c->set_obs_dim(ObservationSize(3));
         c->mutable_obs()->Resize(c->num_unrolls() * c->unroll_length() * ObservationSize(3), 0);
       },
       kInvalidArgument, "obs_dim 97 and act_dim 28; the policy expects 94 and 28"},
      {"NaN reward",
       [](rpc::TrajectoryChunk* c) { c->set_rewards(7, std::numeric_limits<float>::quiet_NaN()); },
       kInvalidArgument, "'rewards' has a non-finite value at index 7"},
      {"unknown node id", [](rpc::TrajectoryChunk* c) { c->set_node(3, kNodes); },
       kInvalidArgument, "unknown node id 2 at step 3 (the graph has 2 nodes)"},
      {"a claim of 2^31 - 1 unrolls with empty arrays",
       [](rpc::TrajectoryChunk* c) {
         const int32_t T = c->unroll_length();
         rpc::TrajectoryChunk empty;
         empty.set_incarnation(c->incarnation());
         empty.set_sequence(c->sequence());
         empty.set_num_parts(1);
         empty.set_obs_dim(c->obs_dim());
         empty.set_act_dim(c->act_dim());
         empty.set_unroll_length(T);
         empty.set_num_unrolls(std::numeric_limits<int32_t>::max());
         *c = empty;
       },
       kInvalidArgument, "chunk claims 2147483647 unrolls"},
      {"labels without their unroll's worth",
       [](rpc::TrajectoryChunk* c) {
         c->set_labelled(std::string(1, '\1'));
         c->mutable_labels()->Resize(c->unroll_length() * kNumActions - 1, 0.5f);
       },
       kInvalidArgument, "chunk field 'labels' has 2799 entries, expected 2800 (1 labelled unrolls)"},
      {"infinite label",
       [](rpc::TrajectoryChunk* c) {
         c->set_labelled(std::string(1, '\1'));
         c->mutable_labels()->Resize(c->unroll_length() * kNumActions, 0.5f);
         c->set_labels(11, -std::numeric_limits<float>::infinity());
       },
       kInvalidArgument, "'labels' has a non-finite value at index 11"},
      {"unregistered incarnation",
       [](rpc::TrajectoryChunk* c) { c->set_incarnation(c->incarnation() + 1000); },
       kFailedPrecondition,
       absl::StrCat("unregistered incarnation ", reg.incarnation() + 1000)},
      {"policy version beyond the learner's",
       [](rpc::TrajectoryChunk* c) {
         c->set_policy_version(1);
       },
       kFailedPrecondition, "chunk policy version 1 is newer than the learner's 0"},
  };
  int64_t sequence = 0;
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    rpc::TrajectoryChunk chunk = ValidChunk(reg, sequence++);
    c.corrupt(&chunk);
    const rpc::ChunkAck ack = send(chunk);
    EXPECT_FALSE(ack.accepted());
    EXPECT_EQ(ack.code(), c.code);
    EXPECT_THAT(ack.message(), HasSubstr(c.message));
    EXPECT_EQ(ack.latest_version(), 0);
  }

  const std::string metrics = Metrics();
  EXPECT_THAT(metrics, HasSubstr("\njuggle_chunks_rejected_total{reason=\"invalid\"} 6\n"));
  EXPECT_THAT(metrics, HasSubstr("\njuggle_chunks_rejected_total{reason=\"unregistered\"} 1\n"));
  EXPECT_THAT(metrics, HasSubstr("\njuggle_chunks_rejected_total{reason=\"unknown_version\"} 1\n"));
  EXPECT_THAT(metrics, Not(HasSubstr("reason=\"stale_version\"")));
  EXPECT_THAT(metrics, Not(HasSubstr("reason=\"queue_full\"")));
  EXPECT_EQ(server_->version(), 0) << "a rejected chunk was trained on";

  // A valid contribution after all that: the one live worker's contribution completes the
  // synchronous batch of version 0, so the learner trains once.
  const rpc::ChunkAck ok = send(ValidChunk(reg, sequence++));
  EXPECT_TRUE(ok.accepted()) << ok.code() << ": " << ok.message();
  EXPECT_EQ(ok.code(), 0);
  EXPECT_TRUE(ok.message().empty()) << ok.message();
  EXPECT_TRUE(WaitUntil([&] { return server_->version() >= 1; }, 8))
      << "the learner did not train on the valid contribution";
  EXPECT_EQ(server_->version(), 1);
  // The training loop publishes the policy before it records the iteration's metrics.
  EXPECT_TRUE(WaitUntil([&] { return server_->metrics().Get("juggle_iterations_total") >= 1; }, 8));
  EXPECT_EQ(server_->metrics().Get("juggle_iterations_total"), 1);
  EXPECT_EQ(server_->metrics().Get("juggle_samples_total"), reg.unroll_length());
  EXPECT_THAT(Metrics(), HasSubstr("\njuggle_policy_version 1\n"));

  // The new policy is served, and a chunk of the old version is now stale (sync: lag 0).
  const Policy p = GetPolicy(reg.incarnation(), 0);
  ASSERT_TRUE(p.status.ok()) << p.status.error_message();
  EXPECT_EQ(p.version, 1);
  const rpc::ChunkAck stale = send(ValidChunk(reg, sequence++));
  EXPECT_FALSE(stale.accepted());
  EXPECT_EQ(stale.code(), kFailedPrecondition);
  EXPECT_THAT(stale.message(), HasSubstr("chunk policy version 0 is more than 0 behind"));
  EXPECT_EQ(stale.latest_version(), 1);
  // A stale chunk is counted by the unrolls it carries, not by the number it claims.
  rpc::TrajectoryChunk liar = ValidChunk(reg, sequence++);
  const int carried = liar.num_unrolls();
  liar.set_num_unrolls(std::numeric_limits<int32_t>::max());
  EXPECT_FALSE(send(liar).accepted());
  EXPECT_EQ(server_->metrics().Get("juggle_unrolls_rejected_total", {{"reason", "stale"}}),
            2 * carried);

  stream->WritesDone();
  const grpc::Status finished = stream->Finish();
  EXPECT_TRUE(finished.ok()) << finished.error_message();
}

TEST_F(RolloutProtocolTest, RegisterRefusesHostileRequestsAndStaysWithinItsLimits) {
  rpc::RegisterResponse resp;
  struct Case {
    const char* name;
    int slot, num_envs;
    std::string host;
    grpc::StatusCode code;
    std::string message;
  };
  const std::vector<Case> cases = {
      {"slot 2^31 - 1", std::numeric_limits<int32_t>::max(), 1, "h",
       grpc::StatusCode::INVALID_ARGUMENT, "slot 2147483647 is outside [-1, 8)"},
      {"50,000,000 envs", -1, 50000000, "h", grpc::StatusCode::INVALID_ARGUMENT,
       "num_envs 50000000 is outside [1, 64]"},
      {"1 MiB host name", -1, 1, std::string(1 << 20, 'x'), grpc::StatusCode::INVALID_ARGUMENT,
       "host name must be 1-253 printable ASCII characters (got 1048576 bytes)"},
      {"2 MiB above the 4 MiB message limit", -1, 1, std::string(6 << 20, 'x'),
       grpc::StatusCode::RESOURCE_EXHAUSTED, ""},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    const grpc::Status s = TryRegister(c.slot, c.num_envs, c.host, &resp);
    EXPECT_EQ(s.error_code(), c.code) << s.error_message();
    EXPECT_THAT(s.error_message(), HasSubstr(c.message));
  }
  // 300 registrations from one host: the first 4 are taken (max_workers_per_host).
  int accepted = 0, exhausted = 0;
  for (int i = 0; i < 300; ++i) {
    const grpc::Status s = TryRegister(-1, 1, "one-host", &resp);
    accepted += s.ok();
    exhausted += s.error_code() == grpc::StatusCode::RESOURCE_EXHAUSTED;
  }
  EXPECT_EQ(accepted, 4);
  EXPECT_EQ(exhausted, 296);
  // Other hosts fill the total of 8.
  for (int i = 0; i < 6; ++i) TryRegister(-1, 1, absl::StrCat("host-", i), &resp);
  EXPECT_EQ(server_->metrics().Get("juggle_workers_connected") <= 8, true);
  EXPECT_EQ(server_->metrics().Get("juggle_registrations_rejected_total", {{"reason", "limit"}}),
            296 + 2);
  EXPECT_EQ(server_->metrics().Get("juggle_registrations_rejected_total", {{"reason", "invalid"}}),
            3);
  // A restarted worker (its slot requested again) still gets in when the learner is full.
  EXPECT_TRUE(TryRegister(0, 1, "one-host", &resp).ok());
}

TEST_F(RolloutProtocolTest, GetPolicyForAFarFutureVersionFailsAtOnce) {
  const rpc::RegisterResponse reg = Register();
  const auto start = Clock::now();
  const Policy p = GetPolicy(reg.incarnation(), int64_t{1} << 40);
  EXPECT_EQ(p.status.error_code(), grpc::StatusCode::OUT_OF_RANGE);
  EXPECT_THAT(p.status.error_message(), HasSubstr("is ahead of the learner's version 0"));
  EXPECT_LT(std::chrono::duration<double>(Clock::now() - start).count(), 5)
      << "answered at once, not after the long-poll";
  EXPECT_EQ(server_->metrics().Get("juggle_policy_requests_rejected_total",
                                   {{"reason", "future_version"}}),
            1);
}

TEST_F(RolloutProtocolTest, ASynchronousRoundGoesOnWithoutAWorkerThatSendsNothing) {
  const rpc::RegisterResponse silent = Register(1, "silent");
  const rpc::RegisterResponse active = Register(1, "active");
  // Keep the silent worker alive with heartbeats while the active one contributes.
  std::atomic<bool> done{false};
  std::thread heartbeats([&] {
    while (!done) {
      grpc::ClientContext ctx;
      SetDeadline(&ctx, 2);
      rpc::HeartbeatRequest req;
      rpc::HeartbeatResponse resp;
      req.set_incarnation(silent.incarnation());
      stub_->Heartbeat(&ctx, req, &resp);
      std::this_thread::sleep_for(std::chrono::milliseconds(300));
    }
  });
  grpc::ClientContext ctx;
  SetDeadline(&ctx, 30);
  auto stream = stub_->StreamTrajectories(&ctx);
  rpc::ChunkAck ack;
  ASSERT_TRUE(stream->Write(ValidChunk(active, 0)));
  ASSERT_TRUE(stream->Read(&ack));
  EXPECT_TRUE(ack.accepted()) << ack.message();
  const auto start = Clock::now();
  EXPECT_TRUE(WaitUntil([&] { return server_->version() >= 1; }, 10))
      << "the round waited for the silent worker past sync_round_timeout_s";
  EXPECT_GE(std::chrono::duration<double>(Clock::now() - start).count(), 1.5)
      << "the round did not wait for the timeout";
  EXPECT_EQ(server_->metrics().Get("juggle_sync_round_stragglers_total"), 1);
  done = true;
  heartbeats.join();
  stream->WritesDone();
  stream->Finish();
}

TEST_F(RolloutProtocolTest, OpenStreamsBeyondTheLimitAreRefusedAtOnce) {
  // max_workers 8: at most 2 × 8 + 16 = 32 streams in flight.
  std::vector<std::unique_ptr<grpc::ClientContext>> contexts;
  std::vector<std::unique_ptr<grpc::ClientReaderWriter<rpc::TrajectoryChunk, rpc::ChunkAck>>> open;
  for (int i = 0; i < 32; ++i) {
    contexts.push_back(std::make_unique<grpc::ClientContext>());
    SetDeadline(contexts.back().get(), 30);
    open.push_back(stub_->StreamTrajectories(contexts.back().get()));
  }
  std::this_thread::sleep_for(std::chrono::seconds(1));  // the server starts every handler
  grpc::ClientContext ctx;
  SetDeadline(&ctx, 10);
  auto extra = stub_->StreamTrajectories(&ctx);
  extra->WritesDone();
  const grpc::Status refused = extra->Finish();
  EXPECT_EQ(refused.error_code(), grpc::StatusCode::RESOURCE_EXHAUSTED) << refused.error_message();
  EXPECT_THAT(refused.error_message(), HasSubstr("more than 32 open trajectory streams"));
  EXPECT_EQ(server_->metrics().Get("juggle_calls_refused_total", {{"rpc", "StreamTrajectories"}}), 1);
  for (auto& stream : open) {
    stream->WritesDone();
    EXPECT_TRUE(stream->Finish().ok());
  }
}

// Ray's RPC fault-tolerance check (issue 47): every handler called twice, as a client retrying
// after a lost response would, leaves the learner as one call does. Register twice for the
// same slot: one live worker (the second incarnation; the first is refused from then on).
// GetPolicy and Heartbeat twice: the same answer, nothing counted. A chunk written twice (the
// first part of a two-part contribution, and its last part after it completed): trained once,
// the copies counted as duplicates, the accounts balanced.
TEST_F(RolloutProtocolTest, EveryHandlerCalledTwiceLeavesTheStateOfOneCall) {
  rpc::RegisterResponse first, again;
  ASSERT_TRUE(TryRegister(3, 2, "retry", &first).ok());
  ASSERT_TRUE(TryRegister(3, 2, "retry", &again).ok());
  EXPECT_EQ(again.slot(), 3);
  EXPECT_NE(again.incarnation(), first.incarnation());
  // The training loop refreshes the gauge every pass.
  const auto connected = [&] { return server_->metrics().Get("juggle_workers_connected"); };
  EXPECT_TRUE(WaitUntil([&] { return connected() == 1; }, 5))
      << "one worker, not two: " << connected();
  EXPECT_EQ(server_->metrics().Get("juggle_worker_restarts_total"), 1);
  EXPECT_EQ(GetPolicy(first.incarnation(), -1).status.error_code(), grpc::StatusCode::FAILED_PRECONDITION)
      << "the replaced incarnation is refused";

  const Policy p1 = GetPolicy(again.incarnation(), -1);
  const Policy p2 = GetPolicy(again.incarnation(), -1);
  ASSERT_TRUE(p1.status.ok() && p2.status.ok());
  EXPECT_EQ(p1.version, p2.version);
  EXPECT_EQ(p1.params, p2.params);
  EXPECT_EQ(p1.edge_counts, p2.edge_counts);

  for (int i = 0; i < 2; ++i) {
    grpc::ClientContext ctx;
    SetDeadline(&ctx);
    rpc::HeartbeatRequest req;
    rpc::HeartbeatResponse resp;
    req.set_incarnation(again.incarnation());
    req.set_policy_version(0);
    req.set_env_steps_per_s(100);
    ASSERT_TRUE(stub_->Heartbeat(&ctx, req, &resp).ok());
    EXPECT_EQ(resp.latest_version(), 0);
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  EXPECT_EQ(connected(), 1);

  // A two-unroll contribution in two parts (one unroll per part).
  const int T = again.unroll_length();
  const std::vector<rpc::TrajectoryChunk> parts = EncodeContribution(
      ValidContribution(2, T, 0), again.incarnation(), 0, size_t(T) * kObsDim * 4);
  ASSERT_EQ(parts.size(), 2u);
  grpc::ClientContext ctx;
  SetDeadline(&ctx, 30);
  auto stream = stub_->StreamTrajectories(&ctx);
  auto send = [&](const rpc::TrajectoryChunk& chunk) {
    rpc::ChunkAck ack;
    EXPECT_TRUE(stream->Write(chunk));
    EXPECT_TRUE(stream->Read(&ack));
    return ack;
  };
  EXPECT_TRUE(send(parts[0]).accepted());
  send(parts[0]);  // the retry; its ack may say accepted: what counts is what is trained
  EXPECT_TRUE(send(parts[1]).accepted());
  ASSERT_TRUE(WaitUntil([&] { return server_->metrics().Get("juggle_iterations_total") >= 1; }, 10))
      << "the contribution was not trained on";
  // The last part again, after the contribution was trained (version 1 now: refused as stale,
  // or taken as a duplicate: either way not trained).
  send(parts[1]);
  std::this_thread::sleep_for(std::chrono::milliseconds(500));
  stream->WritesDone();
  EXPECT_TRUE(stream->Finish().ok());

  EXPECT_EQ(server_->version(), 1) << "trained once";
  EXPECT_EQ(server_->metrics().Get("juggle_samples_total"), 2 * T) << "each unroll trained once";
  EXPECT_EQ(server_->metrics().Get("juggle_unrolls_trained_total"), 2);
  double chosen = 0;
  for (const auto& [labels, value] : server_->metrics().Series("juggle_walk_edge_events_total")) {
    if (labels.count("event") && labels.at("event") == "chosen") chosen += value;
  }
  EXPECT_EQ(chosen, 1) << "the contribution's edge events counted once";
  const double accepted = server_->metrics().Get("juggle_unrolls_accepted_total");
  const double dropped = server_->metrics().Get("juggle_unrolls_dropped_total", {{"reason", "duplicate"}});
  const double rejected = server_->metrics().Get("juggle_unrolls_rejected_total", {{"reason", "stale"}});
  EXPECT_GE(dropped, 1) << "the retried first part was not counted as a duplicate";
  EXPECT_EQ(accepted + rejected, 4) << "4 parts of one unroll each were sent";
  EXPECT_EQ(accepted, 2 + dropped + server_->metrics().Get("juggle_unrolls_partial") +
                          server_->metrics().Get("juggle_unrolls_held"))
      << "accepted = trained + dropped + partial + held";
}

TEST_F(RolloutProtocolTest, HealthServiceReportsServing) {
  // No generated grpc.health.v1 stub is installed: call Check through the generic stub.
  // HealthCheckRequest{service: ""} encodes to no bytes.
  grpc::GenericStub generic(channel_);
  grpc::ClientContext ctx;
  SetDeadline(&ctx);
  grpc::Slice empty("");
  const grpc::ByteBuffer request(&empty, 1);
  grpc::ByteBuffer response;
  std::promise<grpc::Status> done;
  generic.UnaryCall(&ctx, "/grpc.health.v1.Health/Check", grpc::StubOptions(), &request,
                    &response, [&done](grpc::Status s) { done.set_value(std::move(s)); });
  const grpc::Status status = done.get_future().get();
  ASSERT_TRUE(status.ok()) << status.error_code() << ": " << status.error_message();
  std::vector<grpc::Slice> slices;
  ASSERT_TRUE(response.Dump(&slices).ok());
  std::string bytes;
  for (const grpc::Slice& s : slices) bytes.append(reinterpret_cast<const char*>(s.begin()), s.size());
  // HealthCheckResponse{status = 1 (SERVING)}: field 1, varint.
  google::protobuf::UnknownFieldSet fields;
  ASSERT_TRUE(fields.ParseFromString(bytes));
  ASSERT_EQ(fields.field_count(), 1);
  EXPECT_EQ(fields.field(0).number(), 1);
  ASSERT_EQ(fields.field(0).type(), google::protobuf::UnknownField::TYPE_VARINT);
  EXPECT_EQ(fields.field(0).varint(), 1u) << "1 = SERVING";
}

}  // namespace
}  // namespace juggle

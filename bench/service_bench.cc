// Benchmarks of the rollout service, each measured side by side in one run:
//   juggle bench ingest     synthetic workers stream unrolls to a learner over loopback
//   juggle bench broadcast  time until 32 connected workers hold a new policy snapshot
//   juggle bench local      local-mode iteration time vs sampling alone + update alone
// The last line of each is key=value pairs.
#include <grpcpp/grpcpp.h>

#include <atomic>
#include <chrono>
#include <cstdio>
#include <thread>
#include <vector>

#include "absl/strings/str_cat.h"
#include "bench/bench_clock.h"
#include "bench/benchmarks.h"
#include "bench/synthetic_contribution.h"
#include "common/chunk_codec.h"
#include "common/testing/temp_dir.h"
#include "envs/registry.h"
#include "envs/soccer_juggle/spec.h"
#include "learner/learner_server.h"
#include "learner/ppo_trainer.h"
#include "learner/testing/recording_observer.h"
#include "proto/rollout.grpc.pb.h"
#include "worker/env_pool.h"
#include "worker/rollout_collector.h"
#include "worker/worker_client.h"

namespace juggle {
namespace {

using soccer_juggle::JuggleSpec;
using soccer_juggle::kNumActions;
using soccer_juggle::ObservationSize;

using Clock = std::chrono::steady_clock;

absl::StatusOr<std::unique_ptr<LearnerServer>> StartLearner(const LoadedConfig& config,
                                                            bool discard,
                                                            TrainingObserver* observer = nullptr) {
  LearnerOptions o;
  o.config = config;
  // Every synthetic worker registers from this one host.
  o.config.run.mutable_service()->set_max_workers_per_host(o.config.run.service().max_workers());
  o.run_dir = MakeTempDir("juggle_bench_run_");
  o.port = 0;
  o.metrics_port = -1;
  o.listen_all_interfaces = false;
  o.discard_data = discard;
  if (observer != nullptr) o.observers.push_back(observer);
  return LearnerServer::Start(std::move(o));
}

std::unique_ptr<rpc::Rollout::Stub> Stub(int port) {
  grpc::ChannelArguments args;
  args.SetMaxReceiveMessageSize(64 << 20);
  // A separate connection per synthetic worker, as separate processes would have.
  args.SetInt("grpc.channel_id", static_cast<int>(reinterpret_cast<intptr_t>(&args) & 0x7fffffff));
  return rpc::Rollout::NewStub(grpc::CreateCustomChannel(absl::StrCat("127.0.0.1:", port),
                                                         grpc::InsecureChannelCredentials(), args));
}

uint64_t Register(rpc::Rollout::Stub* stub, int envs) {
  grpc::ClientContext ctx;
  rpc::RegisterRequest req;
  req.set_requested_slot(-1);
  req.set_num_envs(envs);
  req.set_hostname("bench");
  rpc::RegisterResponse resp;
  return stub->Register(&ctx, req, &resp).ok() ? resp.incarnation() : 0;
}

}  // namespace

absl::Status RunIngestBench(const IngestBenchOptions& o) {
  absl::StatusOr<LoadedConfig> config = LoadRunConfig(o.config);
  if (!config.ok()) return config.status();
  config->run.mutable_service()->set_synchronous(false);
  config->run.mutable_service()->set_worker_timeout_s(600);
  auto server = StartLearner(*config, /*discard=*/true);
  if (!server.ok()) return server.status();
  std::atomic<bool> stop{false};
  std::thread trainer([&] { (*server)->Train(&stop).IgnoreError(); });

  const int workers = static_cast<int>(o.workers);
  const int T = config->run.ppo().unroll_length();
  const int obs_dim = ObservationSize(config->graph->num_nodes());
  const Contribution c = SyntheticContribution(obs_dim, kNumActions, static_cast<int>(o.unrolls_per_chunk),
                                               T, config->graph->num_nodes());
  std::atomic<int64_t> samples{0}, bytes{0}, rejected{0};
  const double seconds = o.seconds;
  const auto start = Clock::now();
  std::vector<std::thread> threads;
  for (int w = 0; w < workers; ++w) {
    threads.emplace_back([&] {
      auto stub = Stub((*server)->port());
      const uint64_t inc = Register(stub.get(), c.batch.num_unrolls);
      grpc::ClientContext ctx;
      auto stream = stub->StreamTrajectories(&ctx);
      std::vector<rpc::TrajectoryChunk> chunks = EncodeContribution(c, inc, 0, size_t(1) << 30);
      rpc::TrajectoryChunk chunk = chunks[0];
      const int64_t chunk_bytes = static_cast<int64_t>(chunk.ByteSizeLong());
      int64_t seq = 0;
      while (SecondsSince(start) < seconds) {
        chunk.set_sequence(seq++);
        rpc::ChunkAck ack;
        if (!stream->Write(chunk) || !stream->Read(&ack)) break;
        if (!ack.accepted()) {
          ++rejected;
          continue;
        }
        samples += c.batch.num_samples();
        bytes += chunk_bytes;
      }
      stream->WritesDone();
      ctx.TryCancel();
    });
  }
  for (std::thread& t : threads) t.join();
  const double elapsed = SecondsSince(start);
  stop = true;
  trainer.join();
  (*server)->Shutdown();
  const double rate = samples / elapsed;
  std::printf("ingest: %d streams, obs %d, %ld samples in %.1f s, %ld rejected\n", workers, obs_dim,
              static_cast<long>(samples.load()), elapsed, static_cast<long>(rejected.load()));
  std::printf("samples_per_s=%.0f bytes_per_sample=%.1f mb_per_s=%.1f worker_cores_fed=%.1f\n", rate,
              double(bytes) / std::max<int64_t>(1, samples), bytes / elapsed / 1e6, rate / 4000.0);
  return absl::OkStatus();
}

absl::Status RunBroadcastBench(const BroadcastBenchOptions& o) {
  absl::StatusOr<LoadedConfig> config = LoadRunConfig(o.config);
  if (!config.ok()) return config.status();
  const int workers = o.workers;
  const int rounds = o.rounds;
  config->run.mutable_service()->set_synchronous(true);
  config->run.mutable_service()->set_min_workers(workers);
  config->run.mutable_service()->set_worker_timeout_s(600);
  config->run.mutable_ppo()->set_unroll_length(2);
  config->run.mutable_ppo()->set_epochs(1);
  std::atomic<int64_t> published_ns{0};
  IterationCallback published([&](const runlog::IterationRecord&) {
    published_ns = Clock::now().time_since_epoch().count();
  });
  auto server = StartLearner(*config, false, &published);
  if (!server.ok()) return server.status();
  std::atomic<bool> stop{false};
  std::thread trainer([&] { (*server)->Train(&stop).IgnoreError(); });
  const int obs_dim = ObservationSize(config->graph->num_nodes());
  const Contribution c = SyntheticContribution(obs_dim, kNumActions, 1, 2, config->graph->num_nodes());
  std::vector<std::unique_ptr<rpc::Rollout::Stub>> stubs;
  std::vector<uint64_t> incs;
  for (int w = 0; w < workers; ++w) {
    stubs.push_back(Stub((*server)->port()));
    incs.push_back(Register(stubs.back().get(), 1));
  }
  std::vector<double> times;
  int64_t snapshot_bytes = 0;
  for (int round = 0; round < rounds; ++round) {
    const int64_t version = (*server)->version();
    std::vector<int64_t> received_ns(workers, 0);
    std::vector<std::thread> threads;
    for (int w = 0; w < workers; ++w) {
      threads.emplace_back([&, w] {
        Contribution mine = c;
        mine.batch.policy_version.assign(1, version);
        grpc::ClientContext sctx;
        auto stream = stubs[w]->StreamTrajectories(&sctx);
        rpc::ChunkAck ack;
        stream->Write(EncodeContribution(mine, incs[w], round, 1 << 30)[0]);
        stream->Read(&ack);
        stream->WritesDone();
        // Wait for the new snapshot, as a synchronous worker does.
        grpc::ClientContext ctx;
        ctx.set_deadline(std::chrono::system_clock::now() + std::chrono::seconds(60));
        rpc::PolicyRequest req;
        req.set_incarnation(incs[w]);
        req.set_min_version(version);
        auto reader = stubs[w]->GetPolicy(&ctx, req);
        rpc::PolicyChunk chunk;
        int64_t got = 0;
        while (reader->Read(&chunk)) got += chunk.data().size();
        reader->Finish();
        received_ns[w] = Clock::now().time_since_epoch().count();
        if (w == 0) snapshot_bytes = got;
        sctx.TryCancel();
      });
    }
    for (std::thread& t : threads) t.join();
    const int64_t last = *std::max_element(received_ns.begin(), received_ns.end());
    times.push_back((last - published_ns.load()) * 1e-9);
    std::printf("round %d: version %ld -> %ld, all %d workers had the %ld-byte snapshot %.2f ms "
                "after it was published\n",
                round + 1, static_cast<long>(version), static_cast<long>((*server)->version()),
                workers, static_cast<long>(snapshot_bytes), times.back() * 1e3);
  }
  stop = true;
  trainer.join();
  (*server)->Shutdown();
  std::sort(times.begin(), times.end());
  std::printf("broadcast_ms_median=%.2f workers=%d snapshot_bytes=%ld\n", times[times.size() / 2] * 1e3,
              workers, static_cast<long>(snapshot_bytes));
  return absl::OkStatus();
}

absl::Status RunLocalBench(const LocalBenchOptions& o) {
  absl::StatusOr<LoadedConfig> config = LoadRunConfig(o.config);
  if (!config.ok()) return config.status();
  const config::RunConfig& run = config->run;
  const int iterations = o.iterations;
  auto spec = JuggleSpec::Create(*config);
  if (!spec.ok()) return spec.status();
  const int obs_dim = (*spec)->obs_dim();

  // (a) + (b): sampling alone and update alone, the same loop without any service.
  auto pool = EnvPool::Create(*spec, run.sampling().num_envs(), run.sampling().num_threads(), run.seed());
  PpoTrainer trainer(run.model(), run.ppo(), obs_dim, kNumActions, run.seed());
  RolloutCollector collector(pool->get(), run.ppo().unroll_length(), run.seed());
  UnrollBatch batch;
  double sample_s = 0, update_s = 0;
  for (int it = 0; it <= iterations; ++it) {
    const auto t0 = Clock::now();
    auto policy = EigenPolicy::Create(run.model(), trainer.ExportPolicy(), obs_dim, kNumActions);
    if (!collector.Collect(*policy, &batch).ok()) return absl::InternalError("collect failed");
    const auto t1 = Clock::now();
    if (!trainer.Update(batch).ok()) return absl::InternalError("update failed");
    if (it == 0) continue;  // warm-up
    sample_s += std::chrono::duration<double>(t1 - t0).count();
    update_s += SecondsSince(t1);
  }
  sample_s /= iterations;
  update_s /= iterations;

  // (c): local mode — the learner service and one worker over loopback gRPC.
  std::vector<double> iteration_s;
  IterationCallback timed([&](const runlog::IterationRecord& r) {
    if (r.iteration() > 1) iteration_s.push_back(r.iteration_s());  // skip warm-up
  });
  auto server = StartLearner(*config, false, &timed);
  if (!server.ok()) return server.status();
  std::atomic<bool> stop{false}, worker_stop{false};
  std::thread worker([&] {
    WorkerOptions o;
    o.learner_address = absl::StrCat("127.0.0.1:", (*server)->port());
    o.num_envs = run.sampling().num_envs();
    o.num_threads = run.sampling().num_threads();
    o.requested_slot = 0;
    o.stop = &worker_stop;
    o.verbose = false;
    RunWorker(o).IgnoreError();
  });
  std::thread trainer_thread([&] {
    while (!stop && static_cast<int>(iteration_s.size()) < iterations) {
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
    stop = true;
  });
  (*server)->Train(&stop).IgnoreError();
  worker_stop = true;
  worker.join();
  trainer_thread.join();
  (*server)->Shutdown();
  double local = 0;
  for (double t : iteration_s) local += t;
  local /= std::max<size_t>(1, iteration_s.size());
  std::printf("sampling alone %.3f s + update alone %.3f s = %.3f s per iteration; local mode "
              "%.3f s per iteration (%zu iterations)\n",
              sample_s, update_s, sample_s + update_s, local, iteration_s.size());
  std::printf("sample_s=%.4f update_s=%.4f local_iteration_s=%.4f local_over_parts=%.3f\n", sample_s,
              update_s, local, local / (sample_s + update_s));
  return absl::OkStatus();
}

}  // namespace juggle

// `juggle bench soak`: one learner process (`juggle learner`, asynchronous) and N synthetic
// workers (threads, each its own gRPC connection and host name) for a long run with chaos:
// a random worker is killed every kill_every_s — mid-contribution, after the first of its two
// parts — and comes back after 1 s (a restart that replaces its slot) or after the learner's
// worker timeout (forgotten first); half-way the learner is SIGKILLed and restarted with
// --resume. Every 10 s the learner's /metrics and RSS are sampled. At the end the workers stop,
// the learner drains, and the unroll accounts of the resumed learner must reconcile:
// accepted = trained + dropped + held + partial. The last line is key=value pairs.
#include <grpcpp/grpcpp.h>
#include <signal.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <random>
#include <thread>
#include <vector>

#include "absl/strings/str_cat.h"
#include "bench/bench_clock.h"
#include "bench/bench_processes.h"
#include "bench/benchmarks.h"
#include "bench/synthetic_contribution.h"
#include "common/chunk_codec.h"
#include "common/testing/temp_dir.h"
#include "envs/registry.h"
#include "proto/rollout.grpc.pb.h"

namespace juggle {
namespace {

using Clock = std::chrono::steady_clock;

// One synthetic worker: registers in its slot, streams two-part contributions at a steady pace,
// heartbeats, re-registers when the learner forgets it or restarts. `kill` makes it stop after
// the first part of its next contribution, without a goodbye.
class SyntheticWorker {
 public:
  SyntheticWorker(int slot, int port, const Contribution* contribution, double interval_s)
      : slot_(slot), port_(port), contribution_(contribution), interval_s_(interval_s) {
    thread_ = std::thread([this] { Run(); });
  }
  ~SyntheticWorker() {
    kill_ = true;
    if (thread_.joinable()) thread_.join();
  }
  int64_t contributions() const { return contributions_; }

 private:
  std::unique_ptr<rpc::Rollout::Stub> NewStub() {
    grpc::ChannelArguments args;
    args.SetInt("grpc.channel_id", slot_ * 1000 + static_cast<int>(restarts_++ % 1000));
    args.SetMaxReceiveMessageSize(64 << 20);
    return rpc::Rollout::NewStub(grpc::CreateCustomChannel(absl::StrCat("127.0.0.1:", port_),
                                                           grpc::InsecureChannelCredentials(), args));
  }

  void Run() {
    while (!kill_) {
      Session();
      for (int i = 0; i < 5 && !kill_; ++i) std::this_thread::sleep_for(std::chrono::milliseconds(100));
    }
  }

  // One registration: until an RPC fails or kill_.
  void Session() {
    auto stub = NewStub();
    rpc::RegisterResponse reg;
    {
      grpc::ClientContext ctx;
      ctx.set_deadline(std::chrono::system_clock::now() + std::chrono::seconds(5));
      rpc::RegisterRequest req;
      req.set_requested_slot(slot_);
      req.set_num_envs(contribution_->batch.num_unrolls);
      req.set_hostname(absl::StrCat("soak-host-", slot_ % 8));
      if (!stub->Register(&ctx, req, &reg).ok()) return;
    }
    grpc::ClientContext stream_ctx;
    auto stream = stub->StreamTrajectories(&stream_ctx);
    int64_t version = 0;
    auto last_heartbeat = Clock::now();
    // A kill takes effect after the first part of the next contribution.
    for (int64_t sequence = 0;; ++sequence) {
      const auto start = Clock::now();
      Contribution c = *contribution_;
      c.batch.policy_version.assign(c.batch.num_unrolls, version);
      // Two parts (the codec's per-unroll size estimate, half of the unrolls each).
      const UnrollBatch& b = c.batch;
      const size_t per_unroll = size_t(b.unroll_length) * (b.obs_dim + b.act_dim + 4) * 4 + size_t(b.obs_dim) * 4;
      std::vector<rpc::TrajectoryChunk> parts = EncodeContribution(
          c, reg.incarnation(), sequence, per_unroll * std::max(1, b.num_unrolls / 2));
      for (rpc::TrajectoryChunk& part : parts) part.set_policy_version(version);
      for (size_t p = 0; p < parts.size(); ++p) {
        rpc::ChunkAck ack;
        if (!stream->Write(parts[p]) || !stream->Read(&ack)) return;
        version = std::max(version, ack.latest_version());
        if (!ack.accepted()) {
          if (ack.message().find("unregistered") != std::string::npos) return;
          break;  // stale: the next contribution carries the newer version
        }
        if (kill_ && p == 0) {  // dies mid-contribution: the learner holds a partial one
          stream_ctx.TryCancel();
          return;
        }
      }
      ++contributions_;
      if (SecondsSince(last_heartbeat) > 1) {
        grpc::ClientContext ctx;
        ctx.set_deadline(std::chrono::system_clock::now() + std::chrono::seconds(2));
        rpc::HeartbeatRequest req;
        rpc::HeartbeatResponse resp;
        req.set_incarnation(reg.incarnation());
        req.set_policy_version(version);
        if (!stub->Heartbeat(&ctx, req, &resp).ok() || !resp.known()) return;
        last_heartbeat = Clock::now();
      }
      // Now and then download the snapshot, as a real worker does after every new version.
      if (sequence % 20 == 19) {
        grpc::ClientContext ctx;
        ctx.set_deadline(std::chrono::system_clock::now() + std::chrono::seconds(20));
        rpc::PolicyRequest req;
        req.set_incarnation(reg.incarnation());
        req.set_min_version(-1);
        auto reader = stub->GetPolicy(&ctx, req);
        rpc::PolicyChunk chunk;
        while (reader->Read(&chunk)) {
        }
        if (!reader->Finish().ok()) return;
      }
      while (!kill_ && SecondsSince(start) < interval_s_) {
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
      }
    }
  }

  const int slot_, port_;
  const Contribution* contribution_;
  const double interval_s_;
  std::atomic<bool> kill_{false};
  std::atomic<int64_t> contributions_{0};
  int64_t restarts_ = 0;
  std::thread thread_;
};

}  // namespace

absl::Status RunSoakBench(const SoakBenchOptions& o) {
  absl::StatusOr<LoadedConfig> config = LoadAsynchronousConfig(o.config, "the soak");
  if (!config.ok()) return config.status();
  absl::StatusOr<std::shared_ptr<const EnvSpec>> spec = CreateEnvSpec(*config);
  if (!spec.ok()) return spec.status();
  const int T = config->run.ppo().unroll_length();
  const Contribution contribution = SyntheticContribution((*spec)->obs_dim(), (*spec)->act_dim(),
                                                     o.envs_per_worker, T, std::max(1, (*spec)->graph().num_nodes()));
  const std::string dir = o.run_dir.empty() ? MakeTempDir("juggle_soak_") : o.run_dir;
  std::error_code error;
  std::filesystem::create_directories(dir, error);
  if (error) return absl::PermissionDeniedError(absl::StrCat("cannot create ", dir, ": ", error.message()));
  const int port = FreeLoopbackPort(), metrics_port = FreeLoopbackPort();
  auto learner_args = [&](bool resume) {
    std::vector<std::string> a = {"learner", "--config=" + o.config,
                                  "--port=" + std::to_string(port),
                                  "--metrics_port=" + std::to_string(metrics_port),
                                  "--run_dir=" + dir + "/run"};
    if (resume) a.push_back("--resume");
    return a;
  };
  std::printf("soak: %d workers × %d envs, %.0f min, learner kill at %.0f min; logs in %s\n",
              o.workers, o.envs_per_worker, o.minutes, o.minutes / 2, dir.c_str());
  auto learner = std::make_unique<SelfProcess>(learner_args(false), dir + "/learner.log");

  std::vector<std::unique_ptr<SyntheticWorker>> workers(o.workers);
  for (int w = 0; w < o.workers; ++w) {
    workers[w] = std::make_unique<SyntheticWorker>(w, port, &contribution, o.contribution_interval_s);
  }
  std::mt19937_64 rng(o.seed);
  struct Restart {
    int slot;
    Clock::time_point at;
  };
  std::vector<Restart> pending;
  const auto start = Clock::now();
  auto last_kill = start, last_sample = start;
  int worker_kills = 0;
  bool learner_killed = false;
  double rss1_start = -1, rss1_end = -1, rss2_start = -1, rss2_end = -1;
  Accounts before_kill;
  double iteration_at_kill = 0, resumed_at = 0;
  std::string resumed_line;
  const double total_s = o.minutes * 60, warmup_s = std::min(60.0, total_s / 10);
  while (SecondsSince(start) < total_s) {
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
    const double t = SecondsSince(start);
    // Chaos: kill a random live worker; restart the due ones.
    if (std::chrono::duration<double>(Clock::now() - last_kill).count() > o.kill_every_s) {
      last_kill = Clock::now();
      const int slot = static_cast<int>(rng() % o.workers);
      if (workers[slot]) {
        workers[slot].reset();
        ++worker_kills;
        const double down = (rng() % 2 == 0) ? 1.0 : config->run.service().worker_timeout_s() + 2;
        pending.push_back({slot, Clock::now() + std::chrono::milliseconds(int(down * 1000))});
      }
    }
    for (auto it = pending.begin(); it != pending.end();) {
      if (Clock::now() >= it->at) {
        workers[it->slot] = std::make_unique<SyntheticWorker>(it->slot, port, &contribution,
                                                               o.contribution_interval_s);
        it = pending.erase(it);
      } else {
        ++it;
      }
    }
    // The learner dies half-way and comes back from its checkpoint.
    if (!learner_killed && t > total_s / 2) {
      before_kill = Scrape(metrics_port);
      rss1_end = learner->RssMb();
      iteration_at_kill = before_kill.iterations;
      learner->Stop(SIGKILL);
      learner_killed = true;
      std::printf("[%5.0f s] learner SIGKILLed at iteration %.0f; restarting with --resume\n", t,
                  iteration_at_kill);
      std::this_thread::sleep_for(std::chrono::seconds(1));
      // --resume needs a checkpoint (a very short soak may be killed before the first one).
      std::error_code ignored;
      const bool has_checkpoint =
          !std::filesystem::is_empty(dir + "/run/checkpoints", ignored) && !ignored;
      learner = std::make_unique<SelfProcess>(learner_args(has_checkpoint), dir + "/learner.log");
      continue;
    }
    if (std::chrono::duration<double>(Clock::now() - last_sample).count() >= 10) {
      last_sample = Clock::now();
      const Accounts a = Scrape(metrics_port);
      const double rss = learner->RssMb();
      if (!learner_killed && rss1_start < 0 && t > warmup_s) rss1_start = rss;
      if (learner_killed && rss2_start < 0 && a.ok && t > total_s / 2 + warmup_s) rss2_start = rss;
      std::printf("[%5.0f s] rss %.0f MiB  iteration %.0f  workers %.0f  accepted %.0f trained %.0f "
                  "dropped %.0f held %.0f partial %.0f queued %.0f chunks  kills %d\n",
                  t, rss, a.iterations, a.workers, a.accepted, a.trained, a.dropped, a.held,
                  a.partial, a.queued_chunks, worker_kills);
      std::fflush(stdout);
    }
  }
  // Quiesce: workers stop; the learner drains its queue and its accounts stop moving.
  workers.clear();
  Accounts last;
  for (int i = 0; i < 60; ++i) {
    std::this_thread::sleep_for(std::chrono::seconds(1));
    const Accounts a = Scrape(metrics_port);
    if (a.ok && a.queued_chunks == 0 && a.accepted == last.accepted && a.trained == last.trained &&
        a.dropped == last.dropped) {
      last = a;
      break;
    }
    last = a;
  }
  rss2_end = learner->RssMb();
  const double iterations_total = iteration_at_kill + last.iterations;
  {
    std::ifstream log(dir + "/learner.log");
    std::string line;
    while (std::getline(log, line)) {
      if (line.rfind("resumed from", 0) == 0) resumed_line = line;
    }
    const size_t at = resumed_line.find("at iteration ");
    if (at != std::string::npos) resumed_at = std::stod(resumed_line.substr(at + 13));
  }
  const int exit_code = learner->Stop(SIGTERM);
  std::printf("\nlearner 1 (killed): rss %.0f MiB after warm-up -> %.0f MiB at the kill; "
              "iteration %.0f; accounts at the last scrape: accepted %.0f = trained %.0f + "
              "dropped %.0f + held %.0f + partial %.0f (+ %.0f in the queue's %.0f chunks)\n",
              rss1_start, rss1_end, iteration_at_kill, before_kill.accepted, before_kill.trained,
              before_kill.dropped, before_kill.held, before_kill.partial,
              before_kill.unaccounted(), before_kill.queued_chunks);
  std::printf("learner 2 (resumed at iteration %.0f): rss %.0f MiB after warm-up -> %.0f MiB at "
              "the end; exit %d\n", resumed_at, rss2_start, rss2_end, exit_code);
  std::printf("accounts of learner 2 after the drain: accepted %.0f = trained %.0f + dropped %.0f "
              "+ held %.0f + partial %.0f; unaccounted %.0f\n",
              last.accepted, last.trained, last.dropped, last.held, last.partial, last.unaccounted());
  std::string reasons;
  for (const auto& [reason, n] : last.dropped_by_reason) absl::StrAppend(&reasons, " ", reason, "=", n);
  std::printf("dropped by reason:%s\n", reasons.c_str());
  std::printf(
      "soak: minutes=%.1f workers=%d worker_kills=%d learner_kills=1 "
      "iteration_at_kill=%.0f resumed_at_iteration=%.0f iterations_per_minute=%.1f "
      "rss1_start_mb=%.0f rss1_end_mb=%.0f rss2_start_mb=%.0f rss2_end_mb=%.0f "
      "accepted_unrolls=%.0f trained_unrolls=%.0f dropped_unrolls=%.0f held_unrolls=%.0f "
      "partial_unrolls=%.0f unaccounted_unrolls=%.0f\n",
      o.minutes, o.workers, worker_kills, iteration_at_kill, resumed_at,
      iterations_total / std::max(1e-9, SecondsSince(start) / 60), rss1_start, rss1_end, rss2_start,
      rss2_end, last.accepted, last.trained, last.dropped, last.held, last.partial,
      last.unaccounted());
  if (!last.ok) return absl::UnavailableError("the resumed learner did not answer /metrics");
  if (last.unaccounted() != 0) {
    return absl::DataLossError(absl::StrCat(last.unaccounted(), " accepted unrolls are unaccounted for"));
  }
  return absl::OkStatus();
}

}  // namespace juggle

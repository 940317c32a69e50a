// Benchmarks as library functions: each prints its measurements as ratios measured side by side
// in one run, ending with a key=value line (docs/performance.md). `juggle bench <name>`
// (app/bench_command.cc) parses their options.
#ifndef JUGGLE_BENCH_BENCHMARKS_H_
#define JUGGLE_BENCH_BENCHMARKS_H_

#include <cstdint>
#include <memory>
#include <string>

#include "absl/status/status.h"

namespace juggle {

class EigenPolicy;  // common/eigen_policy.h

struct SimBenchOptions {
  std::string config = "configs/right_foot.textproto";
  int envs = 32;      // envs in the pool
  int steps = 300;    // batch steps per measurement
  int repeats = 3;    // alternating repeats of every measurement (best is reported)
};
// Env steps/s on 1 and 2 threads vs bare mj_step of the same states.
absl::Status RunSimBench(const SimBenchOptions& options);

struct PlannerBenchOptions {
  std::string config = "configs/right_foot_planner.textproto";
  int replans = 40;   // re-plans of the planner's own episode per measurement
  int repeats = 2;    // alternating repeats (best is reported)
  std::string planner_set;  // text-format PlannerConfig fields laid over the config's
  // A policy as every plan's prior (planner.policy_prior; may be null): then the same episode
  // is also planned with it, interleaved with the plain planner, and the two are compared.
  std::shared_ptr<const EigenPolicy> proposal;
  std::string proposal_path;  // for the report
};
// The planner's rollouts (1 and 2 threads) and snapshot restores vs bare mj_step; with a
// proposal, the planner with and without it.
absl::Status RunPlannerBench(const PlannerBenchOptions& options);

struct PhysicsBenchOptions {
  std::string config = "configs/right_foot_planner.textproto";
  int states = 2000;  // control steps of a zero-action env replayed
  int repeats = 3;    // rounds over the states (times summed)
};
// mj_step's stages and the model's solver options as variants: substeps/s and physics drift.
absl::Status RunPhysicsBench(const PhysicsBenchOptions& options);

struct MoeBenchOptions {
  int reps = 3;             // repetitions per measurement (best is reported)
  int threads = 2;          // torch threads
  int ppo_samples = 20000;  // samples in the PPO-throughput batch
  int worker_batch = 64;    // batch of the Eigen inference measurement
};
// Layer-wise vs weight-blended MoE, PPO update and Eigen inference speed.
absl::Status RunMoeBench(const MoeBenchOptions& options);

struct IngestBenchOptions {
  std::string config = "configs/full.textproto";  // sets the obs size (full = 157)
  int workers = 4;                                // synthetic worker streams
  double seconds = 5;                             // measurement time
  int unrolls_per_chunk = 8;
};
// Unrolls/s one learner ingests from synthetic workers over loopback.
absl::Status RunIngestBench(const IngestBenchOptions& options);

struct BroadcastBenchOptions {
  std::string config = "configs/full.textproto";  // sets the policy size
  int workers = 32;                               // connected workers
  int rounds = 3;                                 // broadcasts measured
};
// Snapshot broadcast time to connected workers.
absl::Status RunBroadcastBench(const BroadcastBenchOptions& options);

struct LocalBenchOptions {
  std::string config = "configs/right_foot.textproto";
  int iterations = 8;  // iterations of each measurement
};
// Local-mode iteration time vs sampling alone + update alone.
absl::Status RunLocalBench(const LocalBenchOptions& options);

// `juggle bench play` (bench/play_bench.cc).
struct PlayBenchOptions {
  std::string config = "configs/foot_and_head_planner.textproto";
  double phase_seconds = 5;
  int repeats = 2;
  int frame_rate = 60;  // frames per wall second at most, as `juggle play` streams
};
absl::Status RunPlayBench(const PlayBenchOptions& options);

struct DashboardBenchOptions {
  std::string config = "configs/right_foot.textproto";
  double phase_seconds = 30;  // length of each quiet and each polled phase
  int repeats = 2;            // quiet/polled pairs
  double poll_hz = 1;         // page refreshes per second while polled (the page: 1/3)
};

absl::Status RunDashboardBench(const DashboardBenchOptions& options);

struct SoakBenchOptions {
  std::string config = "tests/data/soak.textproto";  // asynchronous
  int workers = 32;                // synthetic workers (threads, one connection each)
  int envs_per_worker = 4;         // unrolls per contribution (sent in two parts)
  double minutes = 30;
  double contribution_interval_s = 0.5;  // each worker's pace
  double kill_every_s = 20;        // a random worker is killed this often
  uint64_t seed = 1;               // of the chaos schedule
  std::string run_dir;             // default: a temporary directory
};
// One learner process and synthetic workers under worker and learner kills: RSS over time and
// the reconciliation of accepted, trained and dropped unrolls (docs/reliability.md).
absl::Status RunSoakBench(const SoakBenchOptions& options);

struct ScaleBenchOptions {
  std::string config = "tests/data/scale.textproto";  // asynchronous
  std::string workers = "8,16,32,64";  // worker process counts, 1 env each
  double warmup_s = 20;
  double seconds = 30;                 // measured per count
};
// One learner process and N worker processes on loopback, per N: samples/s accepted and
// trained, learner CPU and RSS, policy lag, stale drops (docs/performance.md).
absl::Status RunScaleBench(const ScaleBenchOptions& options);

}  // namespace juggle

#endif  // JUGGLE_BENCH_BENCHMARKS_H_

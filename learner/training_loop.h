// The learner's training loop: pops chunk parts off the ingestion queue, assembles batches
// (synchronous: one contribution of the current version from every live worker; asynchronous:
// enough recent unrolls), expires silent workers, applies the walk's edge events, runs the PPO
// update, publishes the new snapshot, reports to its observers (training_observer.h),
// evaluates and checkpoints. Thread-compatible: one thread runs it (the components it shares
// with the gRPC threads are thread-safe).
#ifndef JUGGLE_LEARNER_TRAINING_LOOP_H_
#define JUGGLE_LEARNER_TRAINING_LOOP_H_

#include <atomic>
#include <chrono>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "absl/status/status.h"
#include "absl/status/statusor.h"
#include "common/adaptive_walk.h"
#include "common/bounded_queue.h"
#include "common/metrics.h"
#include "learner/contribution_assembler.h"
#include "learner/demo_buffer.h"
#include "learner/in_run_eval.h"
#include "learner/learner_state.h"
#include "learner/ppo_trainer.h"
#include "learner/sync_round.h"
#include "learner/training_observer.h"
#include "learner/worker_registry.h"
#include "proto/run_config.pb.h"
#include "proto/run_log.pb.h"

namespace juggle {

class TrainingLoop {
 public:
  struct Limits {
    int64_t max_iterations = 0;  // stop at this trainer iteration (0: no limit)
    double max_minutes = 0;      // stop after this long (0: no limit)
  };
  struct Deps {  // all outlive the loop
    const config::ServiceConfig* service;
    PpoTrainer* trainer;
    AdaptiveWalk* walk;
    WorkerRegistry* registry;
    BoundedQueue<ChunkPart>* queue;
    Metrics* metrics;                // the data-flow accounts (accepted, dropped, held, ...)
    RunProgress* progress;           // advanced every iteration (checkpointed with the rest)
    std::atomic<int64_t>* chunks_ingested;
    double control_dt = 0;           // simulated seconds per sample
    std::vector<std::string> outcome_names;
    std::function<void()> publish_snapshot;        // after every update
    std::function<void()> release_workers;         // at the end: no newer policy will come
    // Every checkpoint_every iterations and at the end; returns the file written.
    std::function<absl::StatusOr<std::string>()> checkpoint;
    // The in-run evaluation (may be null or disabled).
    InRunEvaluator* evaluator = nullptr;
    const config::ModelConfig* model = nullptr;  // to rebuild the policy for the evaluation
    int obs_dim = 0, act_dim = 0;
    bool discard_data = false;       // benchmarks: count chunks, never train
    // Who hears of iterations, evaluations, checkpoints and phases, in this order.
    std::vector<TrainingObserver*> observers;
    // Rows of each batch the actor's gate statistics are computed on (0: none).
    int gate_sample_rows = 512;
    // Planner-guided training: its settings and the demonstration buffer (null: off).
    const config::ImitationConfig* imitation = nullptr;
    DemoBuffer* demos = nullptr;
  };
  TrainingLoop(Deps deps, Limits limits);

  // Trains until `stop` is set or a limit is reached; then releases workers waiting for a newer
  // policy and checkpoints. Errors: a checkpoint that cannot be written, an observer's error
  // (training stops there; the final checkpoint is still attempted).
  absl::Status Run(const std::atomic<bool>* stop);

 private:
  using Clock = std::chrono::steady_clock;
  // The live workers of one pass, as the batch rules need them.
  struct Live {
    std::vector<WorkerInfo> workers;
    std::vector<int> slots;
    int envs = 0;
  };
  void Ingest();                                     // one part off the queue, if any
  Live TrackWorkers(Clock::time_point now);          // expiry, gone workers' partials
  std::optional<Contribution> TakeBatch(const Live& live, Clock::time_point now);
  void AccountDrops(int64_t stale);                  // the assembler's losses, by reason
  // The PPO update on `batch`; the walk's events applied, the batch's lag kept for Report.
  // Error: the trainer refused the batch.
  absl::StatusOr<UpdateStats> Train(const Contribution& batch);
  runlog::IterationRecord Report(const Contribution& batch, const UpdateStats& update,
                                 int workers, Clock::time_point t_update, Clock::time_point t_end);
  absl::Status MaybeEvaluate(int64_t iteration);
  absl::Status Checkpoint();
  void SetPhase(LoopPhase phase, std::vector<int> waiting_for = {});
  // Tells every observer; the first error stops the rest.
  template <typename F>
  absl::Status Tell(F hook);

  Deps d_;
  Limits limits_;
  ContributionAssembler assembler_;
  SyncRound round_;
  std::vector<int> reported_slots_;
  int64_t evicted_reported_ = 0, ignored_reported_ = 0;
  int64_t last_checkpoint_iteration_ = -1;  // the final checkpoint skips a repeat of it
  Clock::time_point last_end_;
  WalkEventTotals walk_totals_;                      // since the learner started
  double batch_lag_ = 0;                             // mean policy lag of the last trained batch
  int64_t batch_labelled_ = 0;                       // labelled samples of the last batch
  double fresh_error_ = 0;                           // the policy's error on them (before training)
  int64_t expert_samples_ = 0;                       // expert-driven samples since the learner started
};

}  // namespace juggle

#endif  // JUGGLE_LEARNER_TRAINING_LOOP_H_

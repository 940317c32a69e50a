// The learner's training loop: pops chunk parts off the ingestion queue, assembles batches
// (synchronous: one contribution of the current version from every live worker; asynchronous:
// enough recent unrolls), expires silent workers, applies the walk's edge events, runs the PPO
// update, publishes the new snapshot, reports and checkpoints. Thread-compatible: one thread
// runs it (the components it shares with the gRPC threads are thread-safe).
#ifndef JUGGLE_LEARNER_TRAINING_LOOP_H_
#define JUGGLE_LEARNER_TRAINING_LOOP_H_

#include <atomic>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "absl/status/status.h"
#include "common/adaptive_walk.h"
#include "common/bounded_queue.h"
#include "common/metrics.h"
#include "learner/contribution_assembler.h"
#include "learner/dashboard_state.h"
#include "learner/in_run_eval.h"
#include "learner/learner_metrics.h"
#include "learner/learner_state.h"
#include "learner/ppo_trainer.h"
#include "learner/worker_registry.h"
#include "proto/run_config.pb.h"

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
    Metrics* metrics;
    RunProgress* progress;           // advanced every iteration (checkpointed with the rest)
    std::atomic<int64_t>* chunks_ingested;
    double control_dt = 0;           // simulated seconds per sample
    std::vector<std::string> outcome_names;
    std::function<void()> publish_snapshot;        // after every update
    std::function<void()> release_workers;         // at the end: no newer policy will come
    std::function<absl::Status()> checkpoint;      // every checkpoint_every iterations and at the end
    std::function<void(const IterationReport&)> on_iteration;  // may be empty
    // The in-run evaluation (may be null or disabled) and who hears of its results.
    InRunEvaluator* evaluator = nullptr;
    const config::ModelConfig* model = nullptr;  // to rebuild the policy for the evaluation
    int obs_dim = 0, act_dim = 0;
    std::function<void(const InRunEvaluation&)> on_eval;  // may be empty
    bool discard_data = false;       // benchmarks: count chunks, never train
    // The dashboard's history and the run's phase (may be null).
    DashboardState* dashboard = nullptr;
    // (from, to) node names per graph edge: the labels of the walk's metrics.
    std::vector<std::pair<std::string, std::string>> edge_labels;
    // Rows of each batch the actor's gate statistics are computed on (0: none).
    int gate_sample_rows = 512;
  };
  TrainingLoop(Deps deps, Limits limits) : d_(std::move(deps)), limits_(limits) {}

  // Trains until `stop` is set or a limit is reached; then releases workers waiting for a newer
  // policy and checkpoints. Errors: a checkpoint that cannot be written.
  absl::Status Run(const std::atomic<bool>* stop);

 private:
  Deps d_;
  Limits limits_;
};

}  // namespace juggle

#endif  // JUGGLE_LEARNER_TRAINING_LOOP_H_

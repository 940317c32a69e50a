// The learner's Prometheus metrics: their declarations, the updates of each training event
// (LearnerMetrics, a TrainingObserver) and of the live workers. Thread-safety: the functions
// update a thread-safe Metrics; LearnerMetrics is called by the training thread.
#ifndef JUGGLE_LEARNER_LEARNER_METRICS_H_
#define JUGGLE_LEARNER_LEARNER_METRICS_H_

#include <cstdint>
#include <string>
#include <vector>

#include "common/episode_counters.h"
#include "common/metrics.h"
#include "common/outcome.h"
#include "learner/training_observer.h"
#include "learner/worker_registry.h"
#include "proto/run_log.pb.h"

namespace juggle {

// Declares every learner metric (names, types, help).
void DeclareLearnerMetrics(Metrics* metrics);

// The episodes of `counters` by outcome name (`outcome_names` from the env spec) into
// `outcomes`, zero counts omitted.
void SetOutcomeCounts(const EpisodeCounters& counters,
                      const std::vector<std::string>& outcome_names,
                      google::protobuf::Map<std::string, int32_t>* outcomes);

// Records an iteration: samples, rates, return, completions, PPO statistics, the episodes by
// outcome, the gate statistics and the time of the iteration.
void RecordIteration(const runlog::IterationRecord& record, Metrics* metrics);

// Records that a checkpoint was written now.
void RecordCheckpointTime(Metrics* metrics);

// The walk's per-edge series: counts (juggle_walk_edge_weight) and the events of one
// iteration (juggle_walk_edge_events_total), labelled by the edge's nodes. `edge_labels`
// holds "from->to"-style (from, to) node names per edge.
void RecordWalk(const std::vector<std::pair<std::string, std::string>>& edge_labels,
                const std::vector<double>& counts, const std::vector<int64_t>& chosen,
                const std::vector<int64_t>& completed, const std::vector<int64_t>& failed,
                Metrics* metrics);

// The last in-run evaluation's juggles distribution.
void RecordEvaluation(const runlog::EvaluationRecord& record, Metrics* metrics);

// Per-worker series (heartbeat age, env steps/s) for the live workers; the series of workers
// no longer live are removed. `reported_slots` carries the slots reported last time.
void RecordWorkers(const std::vector<WorkerInfo>& live, WorkerRegistry::Clock::time_point now,
                   std::vector<int>* reported_slots, Metrics* metrics);

// The training events as metric updates. `edge_labels`: (from, to) node names per graph edge.
class LearnerMetrics : public TrainingObserver {
 public:
  LearnerMetrics(Metrics* metrics, std::vector<std::pair<std::string, std::string>> edge_labels)
      : metrics_(metrics), edge_labels_(std::move(edge_labels)) {}
  absl::Status OnIteration(const IterationEvent& event) override;
  absl::Status OnEvaluation(const runlog::EvaluationRecord& record) override;
  absl::Status OnCheckpoint(const runlog::CheckpointRecord& record) override;

 private:
  Metrics* metrics_;  // not owned
  const std::vector<std::pair<std::string, std::string>> edge_labels_;
};

}  // namespace juggle

#endif  // JUGGLE_LEARNER_LEARNER_METRICS_H_

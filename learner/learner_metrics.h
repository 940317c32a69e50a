// What the learner reports: the per-iteration report (progress line, metrics.jsonl record) and
// the Prometheus metric declarations and updates. Thread-safety: IterationReport is a value;
// the functions update a thread-safe Metrics.
#ifndef JUGGLE_LEARNER_LEARNER_METRICS_H_
#define JUGGLE_LEARNER_LEARNER_METRICS_H_

#include <cstdint>
#include <string>
#include <vector>

#include "common/episode_counters.h"
#include "common/metrics.h"
#include "common/outcome.h"
#include "eval/summary.h"
#include "learner/worker_registry.h"

namespace juggle {

// What one training iteration did (for progress lines and metrics files).
struct IterationReport {
  int64_t iteration = 0;
  int64_t total_samples = 0;      // trained on since the run began (across --resume)
  double train_seconds = 0;       // wall time of the run's training (across --resume)
  int64_t samples = 0;
  double samples_per_s = 0;       // over the iteration's wall time
  double sim_s_per_s = 0;
  double mean_return = 0;
  double mean_episode_len = 0;
  double completions_per_episode = 0;
  double juggles_per_episode = 0;
  int64_t episodes = 0;
  double mean_policy_lag = 0;
  double iteration_s = 0;         // wall time since the previous iteration ended
  double wait_s = 0;              // of which waiting for data
  double update_s = 0;            // of which the PPO update
  int workers = 0;
  double value_loss = 0, approx_kl = 0, actor_lr = 0;
  int64_t policy_version = 0;     // after the update
  int queue_depth = 0;            // chunks waiting when the iteration ended
  // Episodes of the iteration by how they ended (outcome name -> count; zero counts omitted).
  std::vector<std::pair<std::string, int64_t>> outcomes;
  // Mixture-of-experts gate statistics of the actor (paper Eq. 4) on a sample of the batch;
  // negative when the actor is not a mixture.
  double gate_specialization = -1, gate_utilization = -1;
  std::string latest_eval;        // the last in-run evaluation, short (progress line only)
  // One metrics.jsonl record (a JSON object on one line).
  std::string ToJson() const;
  std::string ToLine() const;
};

// Declares every learner metric (names, types, help).
void DeclareLearnerMetrics(Metrics* metrics);

// The episodes of `counters` by outcome name (`outcome_names` from the env spec), zero
// counts omitted.
std::vector<std::pair<std::string, int64_t>> OutcomeCounts(
    const EpisodeCounters& counters, const std::vector<std::string>& outcome_names);

// Records an iteration: samples, rates, return, completions, PPO statistics, the episodes by
// outcome, the gate statistics and the time of the iteration.
void RecordIteration(const IterationReport& report, Metrics* metrics);

// Records that a checkpoint was written now.
void RecordCheckpointTime(Metrics* metrics);

// The walk's per-edge series: counts (juggle_walk_edge_weight) and the events of one
// iteration (juggle_walk_edge_events_total), labelled by the edge's nodes. `edge_labels`
// holds "from->to"-style (from, to) node names per edge.
void RecordWalk(const std::vector<std::pair<std::string, std::string>>& edge_labels,
                const std::vector<double>& counts, const std::vector<int64_t>& chosen,
                const std::vector<int64_t>& completed, const std::vector<int64_t>& failed,
                Metrics* metrics);

// The last in-run evaluation's juggles distribution (eval/summary.h).
void RecordEvaluation(const EvalSummary& summary, Metrics* metrics);

// Per-worker series (heartbeat age, env steps/s) for the live workers; the series of workers
// no longer live are removed. `reported_slots` carries the slots reported last time.
void RecordWorkers(const std::vector<WorkerInfo>& live, WorkerRegistry::Clock::time_point now,
                   std::vector<int>* reported_slots, Metrics* metrics);

}  // namespace juggle

#endif  // JUGGLE_LEARNER_LEARNER_METRICS_H_

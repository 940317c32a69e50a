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
  std::string latest_eval;        // the last in-run evaluation, short (progress line only)
  std::string ToJson() const;
  std::string ToLine() const;
};

// Declares every learner metric (names, types, help).
void DeclareLearnerMetrics(Metrics* metrics);

// Records an iteration: samples, rates, return, completions and the episodes by outcome
// (`outcome_names` from the env spec).
void RecordIteration(const IterationReport& report, const EpisodeCounters& episodes,
                     const std::vector<std::string>& outcome_names, Metrics* metrics);

// The last in-run evaluation's juggles distribution (eval/summary.h).
void RecordEvaluation(const EvalSummary& summary, Metrics* metrics);

// Per-worker series (heartbeat age, env steps/s) for the live workers; the series of workers
// no longer live are removed. `reported_slots` carries the slots reported last time.
void RecordWorkers(const std::vector<WorkerInfo>& live, WorkerRegistry::Clock::time_point now,
                   std::vector<int>* reported_slots, Metrics* metrics);

}  // namespace juggle

#endif  // JUGGLE_LEARNER_LEARNER_METRICS_H_

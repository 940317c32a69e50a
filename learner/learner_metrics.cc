#include "learner/learner_metrics.h"

#include <algorithm>
#include <chrono>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"

namespace juggle {

std::string IterationReport::ToJson() const {
  return absl::StrFormat(
      "{\"iteration\": %d, \"samples\": %d, \"train_s\": %.1f, \"samples_per_s\": %.1f, "
      "\"sim_s_per_s\": %.2f, \"mean_return\": %.4f, \"mean_episode_len\": %.2f, "
      "\"completions_per_episode\": %.3f, \"juggles_per_episode\": %.3f, \"episodes\": %d, "
      "\"policy_lag\": %.3f, \"iteration_s\": %.3f, \"wait_s\": %.3f, \"update_s\": %.3f, "
      "\"workers\": %d, \"value_loss\": %.5f, \"approx_kl\": %.5f, \"actor_lr\": %.6f}",
      iteration, total_samples, train_seconds, samples_per_s, sim_s_per_s, mean_return,
      mean_episode_len, completions_per_episode, juggles_per_episode, episodes, mean_policy_lag,
      iteration_s, wait_s, update_s, workers, value_loss, approx_kl, actor_lr);
}

std::string IterationReport::ToLine() const {
  std::string line = absl::StrFormat(
      "iter %5d  samples %9d  %7.0f samples/s  %5.1f sim-s/s  return %7.3f  ep_len %6.1f  "
      "juggles/ep %5.2f  lag %.2f  workers %d  %.2fs (wait %.2f, update %.2f)",
      iteration, total_samples, samples_per_s, sim_s_per_s, mean_return, mean_episode_len,
      juggles_per_episode, mean_policy_lag, workers, iteration_s, wait_s, update_s);
  if (!latest_eval.empty()) absl::StrAppend(&line, "  | ", latest_eval);
  return line;
}

void DeclareLearnerMetrics(Metrics* m) {
  m->Declare("juggle_samples_total", "counter", "Environment steps trained on.");
  m->Declare("juggle_samples_per_second", "gauge", "Samples per second over the last iteration.");
  m->Declare("juggle_sim_seconds_per_second", "gauge", "Simulated seconds per wall second.");
  m->Declare("juggle_queue_depth", "gauge", "Chunks waiting in the ingestion queue.");
  m->Declare("juggle_policy_lag", "histogram",
             "Versions between an unroll's policy and the trained one.", {0, 1, 2, 3, 5, 10});
  m->Declare("juggle_chunks_rejected_total", "counter", "Chunks rejected, by reason.");
  m->Declare("juggle_unrolls_dropped_total", "counter",
             "Accepted unrolls never trained on, by reason.");
  m->Declare("juggle_policy_requests_rejected_total", "counter",
             "GetPolicy calls refused, by reason.");
  m->Declare("juggle_workers_connected", "gauge", "Live workers.");
  m->Declare("juggle_worker_heartbeat_age_seconds", "gauge",
             "Seconds since each worker's last sign of life.");
  m->Declare("juggle_worker_env_steps_per_second", "gauge",
             "Env steps per second reported by each worker.");
  m->Declare("juggle_worker_restarts_total", "counter", "Registrations that replaced a live slot.");
  m->Declare("juggle_worker_timeouts_total", "counter", "Workers forgotten after missing heartbeats.");
  m->Declare("juggle_policy_version", "gauge", "Current policy version.");
  m->Declare("juggle_iterations_total", "counter", "PPO iterations.");
  m->Declare("juggle_mean_return", "gauge", "Mean episode return over the last iteration.");
  m->Declare("juggle_completions_per_episode", "gauge",
             "Node completions per episode, last iteration.");
  m->Declare("juggle_juggles_per_episode", "gauge", "Juggles per episode, last iteration.");
  m->Declare("juggle_episodes_total", "counter", "Episodes ended, by outcome.");
  m->Declare("juggle_eval_median_juggles", "gauge",
             "Median juggles per episode of the last in-run evaluation.");
  m->Declare("juggle_eval_frac_juggles_ge_10", "gauge",
             "Fraction of the last in-run evaluation's episodes with at least 10 juggles.");
  m->Declare("juggle_evaluations_total", "counter", "In-run evaluations run.");
}

void RecordEvaluation(const EvalSummary& summary, Metrics* m) {
  m->Set("juggle_eval_median_juggles", summary.median_juggles);
  m->Set("juggle_eval_frac_juggles_ge_10", summary.frac_juggles_ge_10);
  m->Add("juggle_evaluations_total", 1);
}

void RecordIteration(const IterationReport& r, const EpisodeCounters& ep,
                     const std::vector<std::string>& outcome_names, Metrics* m) {
  m->Add("juggle_samples_total", static_cast<double>(r.samples));
  m->Set("juggle_samples_per_second", r.samples_per_s);
  m->Set("juggle_sim_seconds_per_second", r.sim_s_per_s);
  m->Add("juggle_iterations_total", 1);
  m->Set("juggle_mean_return", r.mean_return);
  m->Set("juggle_completions_per_episode", r.completions_per_episode);
  m->Set("juggle_juggles_per_episode", r.juggles_per_episode);
  for (size_t o = 0; o < ep.outcomes.size(); ++o) {
    if (ep.outcomes[o] == 0) continue;
    m->Add("juggle_episodes_total", static_cast<double>(ep.outcomes[o]),
           {{"outcome", OutcomeName(outcome_names, static_cast<Outcome>(o))}});
  }
}

void RecordWorkers(const std::vector<WorkerInfo>& live, WorkerRegistry::Clock::time_point now,
                   std::vector<int>* reported_slots, Metrics* m) {
  std::vector<int> live_slots;
  for (const WorkerInfo& w : live) {
    live_slots.push_back(w.slot);
    const std::string slot = absl::StrCat(w.slot);
    m->Set("juggle_worker_heartbeat_age_seconds",
           std::chrono::duration<double>(now - w.last_seen).count(), {{"slot", slot}});
    m->Set("juggle_worker_env_steps_per_second", w.env_steps_per_s, {{"slot", slot}});
  }
  for (int slot : *reported_slots) {
    if (std::find(live_slots.begin(), live_slots.end(), slot) != live_slots.end()) continue;
    m->Erase("juggle_worker_heartbeat_age_seconds", "slot", absl::StrCat(slot));
    m->Erase("juggle_worker_env_steps_per_second", "slot", absl::StrCat(slot));
  }
  *reported_slots = std::move(live_slots);
  m->Set("juggle_workers_connected", static_cast<double>(live.size()));
}

}  // namespace juggle

#include "learner/learner_metrics.h"

#include <algorithm>
#include <chrono>

#include "absl/strings/str_cat.h"

namespace juggle {

void DeclareLearnerMetrics(Metrics* m) {
  // Throughput.
  m->Declare("juggle_samples_total", "counter", "Environment steps trained on.");
  m->Declare("juggle_simulated_seconds_total", "counter",
             "Simulated seconds trained on (samples times the control step).");
  m->Declare("juggle_samples_per_second", "gauge", "Samples per second over the last iteration.");
  m->Declare("juggle_sim_seconds_per_second", "gauge",
             "Simulated seconds per wall second over the last iteration.");
  m->Declare("juggle_iteration_wait_seconds_total", "counter",
             "Wall time the training loop spent waiting for data.");
  m->Declare("juggle_iteration_update_seconds_total", "counter",
             "Wall time the training loop spent in PPO updates.");
  m->Declare("juggle_ingest_queue_chunks", "gauge", "Chunks waiting in the ingestion queue.");
  m->Declare("juggle_ingest_queue_capacity_chunks", "gauge",
             "Capacity of the ingestion queue (service.queue_capacity).");
  m->Declare("juggle_policy_broadcast_seconds", "histogram",
              "Time from a policy version's publication until every worker live then has "
              "received it (or a newer one).",
              {0.005, 0.01, 0.025, 0.05, 0.1, 0.25, 0.5, 1, 2.5, 5, 10});
  m->Declare("juggle_policy_lag_versions", "histogram",
             "Versions between an unroll's policy and the trained one.", {0, 1, 2, 3, 5, 10});
  m->Declare("juggle_chunks_rejected_total", "counter", "Chunks rejected, by reason.");
  // Unroll accounting: accepted = trained + dropped + held + partial (+ queued), so nothing a
  // worker was told was accepted goes unaccounted (docs/reliability.md, the soak bench).
  m->Declare("juggle_unrolls_accepted_total", "counter",
             "Unrolls of chunks accepted (acked) and queued for training.");
  m->Declare("juggle_unrolls_trained_total", "counter", "Unrolls PPO updates were computed on.");
  m->Declare("juggle_unrolls_rejected_total", "counter",
             "Unrolls of chunks refused at ingestion (never accepted), by reason (stale).");
  m->Declare("juggle_unrolls_held", "gauge",
             "Unrolls in complete contributions waiting for a batch.");
  m->Declare("juggle_unrolls_partial", "gauge",
             "Unrolls in contributions still missing parts.");
  m->Declare("juggle_unrolls_dropped_total", "counter",
             "Accepted unrolls never trained on, by reason (stale, overflow, worker_gone, "
             "inconsistent_parts, duplicate, update, discarded).");
  m->Declare("juggle_policy_requests_rejected_total", "counter",
             "GetPolicy calls refused, by reason.");
  // Workers.
  m->Declare("juggle_workers_connected", "gauge", "Live workers.");
  m->Declare("juggle_workers_needed", "gauge",
             "Live workers an iteration needs (synchronous: service.min_workers; else 1).");
  m->Declare("juggle_worker_heartbeat_age_seconds", "gauge",
             "Seconds since each worker's last sign of life.");
  m->Declare("juggle_worker_env_steps_per_second", "gauge",
             "Env steps per second reported by each worker.");
  m->Declare("juggle_worker_envs", "gauge", "Envs each worker simulates.");
  m->Declare("juggle_worker_chunks_total", "counter",
             "Chunks from each live worker, by result (accepted, rejected).");
  m->Declare("juggle_worker_restarts_total", "counter", "Registrations that replaced a live slot.");
  m->Declare("juggle_worker_reconnects_total", "counter",
             "Registrations from worker processes that had registered before (they say how many "
             "times), by slot: reconnects after a lost connection or a learner restart.");
  m->Declare("juggle_worker_timeouts_total", "counter", "Workers forgotten after missing heartbeats.");
  m->Declare("juggle_registrations_rejected_total", "counter",
             "Registrations refused, by reason (limit: service.max_workers or "
             "max_workers_per_host; invalid: slot, env count or host name).");
  m->Declare("juggle_calls_refused_total", "counter",
             "Long-lived calls refused beyond 2 × service.max_workers + 16 in flight, by RPC.");
  m->Declare("juggle_rpcs_unauthenticated_total", "counter",
             "RPCs refused for a missing or wrong token, by RPC.");
  m->Declare("juggle_sync_round_stragglers_total", "counter",
             "Synchronous rounds that went on without a silent worker "
             "(service.sync_round_timeout_s).");
  // Training.
  m->Declare("juggle_run_info", "gauge",
             "Always 1; the run's config name, family and mode as labels.");
  m->Declare("juggle_learner_start_time_seconds", "gauge",
             "Unix time the learner started.");
  m->Declare("juggle_policy_version", "gauge", "Current policy version.");
  m->Declare("juggle_iterations_total", "counter", "PPO iterations.");
  m->Declare("juggle_last_iteration_timestamp_seconds", "gauge",
             "Unix time the last iteration ended.");
  m->Declare("juggle_last_checkpoint_timestamp_seconds", "gauge",
             "Unix time the last checkpoint was written.");
  m->Declare("juggle_mean_return", "gauge", "Mean episode return over the last iteration.");
  m->Declare("juggle_episode_length_steps", "gauge",
             "Mean episode length in control steps over the last iteration.");
  m->Declare("juggle_completions_per_episode", "gauge",
             "Node completions per episode, last iteration.");
  m->Declare("juggle_juggles_per_episode", "gauge", "Juggles per episode, last iteration.");
  m->Declare("juggle_episodes_total", "counter", "Episodes ended, by outcome.");
  m->Declare("juggle_value_loss", "gauge", "Critic loss of the last PPO update.");
  m->Declare("juggle_approx_kl", "gauge", "Approximate KL of the last PPO update.");
  m->Declare("juggle_learning_rate", "gauge", "Actor learning rate of the last PPO update.");
  m->Declare("juggle_moe_gate_specialization", "gauge",
             "Mixture-of-experts specialization (paper Eq. 4) on a sample of the last batch.");
  m->Declare("juggle_moe_gate_utilization", "gauge",
             "Mixture-of-experts utilization (paper Eq. 4; 1/K = all experts used equally).");
  // Planner-guided training (proto/imitation.proto).
  m->Declare("juggle_imitation_loss", "gauge",
             "Mean squared label error of the actor on the demonstrations, last update.");
  m->Declare("juggle_imitation_weight", "gauge",
             "Weight of the imitation term in the actor loss (0 while only cloning).");
  m->Declare("juggle_labelled_share", "gauge",
             "Labelled samples / samples received, last iteration.");
  m->Declare("juggle_demo_buffer_states", "gauge", "States in the demonstration buffer.");
  m->Declare("juggle_demo_labels_total", "counter",
             "Labelled states added to the demonstration buffer (evicted = this - buffer).");
  m->Declare("juggle_expert_juggles_per_episode", "gauge",
             "Juggles per episode of the expert-driven envs, last iteration with one.");
  // The expert-iteration loop (issue 48): what the planner spends on the labels.
  m->Declare("juggle_expert_labels_total", "counter", "Env steps the planner labelled.");
  m->Declare("juggle_expert_replans_total", "counter", "Re-plans of the labelling planner.");
  m->Declare("juggle_expert_rollout_steps_total", "counter",
             "Control steps the labelling planner's rollouts simulated.");
  m->Declare("juggle_expert_rescues_total", "counter",
             "Re-plans of the labelling planner that ran the rescue search.");
  m->Declare("juggle_expert_proposal_tried_total", "counter",
             "Re-plans that tried the learned policy alone (planner.policy_prior).");
  m->Declare("juggle_expert_proposal_chosen_total", "counter",
             "Re-plans that chose the learned policy alone (its share of chosen candidates).");
  m->Declare("juggle_expert_proposal_weight_total", "counter",
             "The chosen plans' weight of the learned policy, summed over the re-plans that "
             "tried it (/ juggle_expert_proposal_tried_total: the mean trust).");
  // The adaptive walk (labels: the edge's nodes; bounded by the graph).
  m->Declare("juggle_walk_edge_weight", "gauge",
             "Adaptive-walk count of each control-graph edge (sampling weight).");
  m->Declare("juggle_walk_edge_events_total", "counter",
             "Workers' edge events applied by the learner, by edge and event "
             "(chosen, completed, failed).");
  // In-run evaluation.
  m->Declare("juggle_eval_median_juggles", "gauge",
             "Median juggles per episode of the last in-run evaluation.");
  m->Declare("juggle_eval_juggles_ge_10_ratio", "gauge",
             "Fraction of the last in-run evaluation's episodes with at least 10 juggles.");
  m->Declare("juggle_evaluations_total", "counter", "In-run evaluations run.");
}

void RecordEvaluation(const runlog::EvaluationRecord& r, Metrics* m) {
  m->Set("juggle_eval_median_juggles", r.median_juggles());
  m->Set("juggle_eval_juggles_ge_10_ratio", r.frac_juggles_ge_10());
  m->Add("juggle_evaluations_total", 1);
}

void SetOutcomeCounts(const EpisodeCounters& ep, const std::vector<std::string>& outcome_names,
                      google::protobuf::Map<std::string, int32_t>* outcomes) {
  for (size_t o = 0; o < ep.outcomes.size(); ++o) {
    if (ep.outcomes[o] == 0) continue;
    (*outcomes)[OutcomeName(outcome_names, static_cast<Outcome>(o))] =
        static_cast<int32_t>(ep.outcomes[o]);
  }
}

void RecordIteration(const runlog::IterationRecord& r, Metrics* m) {
  m->Add("juggle_samples_total", static_cast<double>(r.iteration_samples()));
  if (r.samples_per_s() > 0) {
    m->Add("juggle_simulated_seconds_total",
           r.iteration_samples() * r.sim_s_per_s() / r.samples_per_s());
  }
  m->Set("juggle_samples_per_second", r.samples_per_s());
  m->Set("juggle_sim_seconds_per_second", r.sim_s_per_s());
  m->Add("juggle_iteration_wait_seconds_total", r.wait_s());
  m->Add("juggle_iteration_update_seconds_total", r.update_s());
  m->Add("juggle_iterations_total", 1);
  m->Set("juggle_last_iteration_timestamp_seconds", UnixNow());
  m->Set("juggle_mean_return", r.mean_return());
  m->Set("juggle_episode_length_steps", r.mean_episode_len());
  m->Set("juggle_completions_per_episode", r.completions_per_episode());
  m->Set("juggle_juggles_per_episode", r.juggles_per_episode());
  m->Set("juggle_value_loss", r.value_loss());
  m->Set("juggle_approx_kl", r.approx_kl());
  m->Set("juggle_learning_rate", r.actor_lr());
  m->Set("juggle_imitation_loss", r.imitation_loss());
  m->Set("juggle_imitation_weight", r.imitation_weight());
  m->Set("juggle_labelled_share", r.labelled_share());
  m->Set("juggle_demo_buffer_states", r.demo_buffer());
  if (r.expert_episodes() > 0) {
    m->Set("juggle_expert_juggles_per_episode", r.expert_juggles_per_episode());
  }
  m->Add("juggle_expert_labels_total", r.expert_labels());
  m->Add("juggle_expert_replans_total", r.expert_replans());
  m->Add("juggle_expert_rollout_steps_total", r.expert_rollout_steps());
  m->Add("juggle_expert_rescues_total", r.expert_rescues());
  m->Add("juggle_expert_proposal_tried_total", r.expert_proposal_tried());
  m->Add("juggle_expert_proposal_chosen_total", r.expert_proposal_chosen());
  m->Add("juggle_expert_proposal_weight_total", r.expert_proposal_weight_sum());
  if (r.has_gate_specialization()) {
    m->Set("juggle_moe_gate_specialization", r.gate_specialization());
    m->Set("juggle_moe_gate_utilization", r.gate_utilization());
  }
  for (const auto& [name, count] : r.outcomes()) {
    m->Add("juggle_episodes_total", static_cast<double>(count), {{"outcome", name}});
  }
}

void RecordCheckpointTime(Metrics* m) {
  m->Set("juggle_last_checkpoint_timestamp_seconds", UnixNow());
}

void RecordWalk(const std::vector<std::pair<std::string, std::string>>& edge_labels,
                const std::vector<double>& counts, const std::vector<int64_t>& chosen,
                const std::vector<int64_t>& completed, const std::vector<int64_t>& failed,
                Metrics* m) {
  for (size_t e = 0; e < edge_labels.size(); ++e) {
    const std::map<std::string, std::string> edge = {{"from", edge_labels[e].first},
                                                     {"to", edge_labels[e].second}};
    if (e < counts.size()) m->Set("juggle_walk_edge_weight", counts[e], edge);
    const std::pair<const char*, const std::vector<int64_t>*> events[] = {
        {"chosen", &chosen}, {"completed", &completed}, {"failed", &failed}};
    for (const auto& [event, values] : events) {
      if (e >= values->size()) continue;
      std::map<std::string, std::string> labels = edge;
      labels["event"] = event;
      m->Add("juggle_walk_edge_events_total", static_cast<double>((*values)[e]), labels);
    }
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
    m->Set("juggle_worker_envs", w.num_envs, {{"slot", slot}});
    m->Set("juggle_worker_chunks_total", static_cast<double>(w.chunks_accepted),
           {{"slot", slot}, {"result", "accepted"}});
    m->Set("juggle_worker_chunks_total", static_cast<double>(w.chunks_rejected),
           {{"slot", slot}, {"result", "rejected"}});
  }
  for (int slot : *reported_slots) {
    if (std::find(live_slots.begin(), live_slots.end(), slot) != live_slots.end()) continue;
    for (const char* name : {"juggle_worker_heartbeat_age_seconds",
                             "juggle_worker_env_steps_per_second", "juggle_worker_envs",
                             "juggle_worker_chunks_total"}) {
      m->Erase(name, "slot", absl::StrCat(slot));
    }
  }
  *reported_slots = std::move(live_slots);
  m->Set("juggle_workers_connected", static_cast<double>(live.size()));
}

absl::Status LearnerMetrics::OnIteration(const IterationEvent& event) {
  RecordIteration(event.record, metrics_);
  if (!edge_labels_.empty()) {
    RecordWalk(edge_labels_, event.edge_counts, event.walk_events.chosen,
               event.walk_events.completed, event.walk_events.failed, metrics_);
  }
  return absl::OkStatus();
}

absl::Status LearnerMetrics::OnEvaluation(const runlog::EvaluationRecord& record) {
  RecordEvaluation(record, metrics_);
  return absl::OkStatus();
}

absl::Status LearnerMetrics::OnCheckpoint(const runlog::CheckpointRecord&) {
  RecordCheckpointTime(metrics_);
  return absl::OkStatus();
}

}  // namespace juggle

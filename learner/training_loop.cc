#include "learner/training_loop.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <optional>

#include "absl/strings/str_cat.h"
#include "common/eigen_policy.h"
#include "learner/sync_round.h"

namespace juggle {
namespace {

using Clock = std::chrono::steady_clock;

double Seconds(Clock::duration d) { return std::chrono::duration<double>(d).count(); }

// The actor's gate statistics (paper Eq. 4) on up to `rows` observations of `batch`, taken at
// an even stride; negative when the actor is not a mixture. Costs one gate forward pass.
void GateStatisticsOfBatch(const PpoTrainer& trainer, const UnrollBatch& batch, int rows,
                           IterationReport* r) {
  const int64_t n = batch.num_samples();
  if (rows <= 0 || n == 0) return;
  const int64_t take = std::min<int64_t>(rows, n);
  const int64_t stride = n / take;
  std::vector<float> obs(static_cast<size_t>(take) * batch.obs_dim);
  for (int64_t i = 0; i < take; ++i) {
    std::copy_n(batch.obs.begin() + i * stride * batch.obs_dim, batch.obs_dim,
                obs.begin() + i * batch.obs_dim);
  }
  int experts = 0;
  const std::vector<float> gates = trainer.ActorGates(obs.data(), take, &experts);
  if (experts == 0) return;
  const RowMatrix g = Eigen::Map<const RowMatrix>(gates.data(), take, experts);
  const GateStatistics stats = ComputeGateStatistics(g);
  r->gate_specialization = stats.specialization;
  r->gate_utilization = stats.utilization;
}

}  // namespace

absl::Status TrainingLoop::Run(const std::atomic<bool>* stop) {
  const config::ServiceConfig& svc = *d_.service;
  const auto start = Clock::now();
  // What it may hold per worker: the versions a batch can use, plus one of slack.
  ContributionAssembler assembler(svc.synchronous() ? 2 : svc.max_policy_lag() + 2,
                                  svc.synchronous() ? 0 : svc.unrolls_per_iteration());
  int64_t evicted_reported = 0, ignored_reported = 0;
  SyncRound round;
  std::vector<int> reported_slots;
  auto last_end = Clock::now();
  std::string latest_eval;
  auto phase = [this](LoopPhase p) {
    if (d_.dashboard != nullptr) d_.dashboard->SetPhase(p);
  };
  auto checkpoint = [&] {
    phase(LoopPhase::kCheckpointing);
    absl::Status s = d_.checkpoint();
    phase(LoopPhase::kWaitingForData);
    return s;
  };
  phase(LoopPhase::kWaitingForData);
  while (!stop->load()) {
    if (limits_.max_iterations > 0 && d_.trainer->iteration() >= limits_.max_iterations) break;
    if (limits_.max_minutes > 0 && Seconds(Clock::now() - start) > limits_.max_minutes * 60) break;
    if (std::optional<ChunkPart> part = d_.queue->Pop(Clock::now() + std::chrono::milliseconds(100))) {
      ++*d_.chunks_ingested;
      const int unrolls = part->data.batch.num_unrolls;
      if (d_.discard_data) {
        d_.metrics->Add("juggle_unrolls_dropped_total", unrolls, {{"reason", "discarded"}});
        continue;
      }
      if (absl::Status added = assembler.Add(std::move(*part)); !added.ok()) {
        d_.metrics->Add("juggle_chunks_rejected_total", 1, {{"reason", "inconsistent_parts"}});
        d_.metrics->Add("juggle_unrolls_dropped_total", unrolls, {{"reason", "inconsistent_parts"}});
        std::fprintf(stderr, "warning: %s\n", std::string(added.message()).c_str());
      }
    }
    d_.metrics->Set("juggle_ingest_queue_chunks", static_cast<double>(d_.queue->size()));
    const auto now = Clock::now();
    for (uint64_t dead : d_.registry->Expire(now, std::chrono::duration<double>(svc.worker_timeout_s()))) {
      d_.metrics->Add("juggle_worker_timeouts_total", 1);
      std::printf("worker incarnation %lx timed out; its partial data is discarded\n",
                  static_cast<unsigned long>(dead));
    }
    const std::vector<WorkerInfo> live = d_.registry->Live();
    std::vector<uint64_t> live_incarnations;
    std::vector<int> live_slots;
    int live_envs = 0;
    for (const WorkerInfo& w : live) {
      live_incarnations.push_back(w.incarnation);
      live_slots.push_back(w.slot);
      live_envs += w.num_envs;
    }
    const int64_t partial_before = assembler.partial_unrolls();
    assembler.DropAllBut(live_incarnations);
    if (const int64_t gone = partial_before - assembler.partial_unrolls(); gone > 0) {
      d_.metrics->Add("juggle_unrolls_dropped_total", static_cast<double>(gone),
                      {{"reason", "worker_gone"}});
    }
    RecordWorkers(live, now, &reported_slots, d_.metrics);

    // A batch for the current version, by mode.
    const int64_t version = d_.trainer->version();
    int64_t dropped = 0;
    std::optional<Contribution> batch;
    if (svc.synchronous()) {
      if (static_cast<int>(live.size()) >= std::max(1, svc.min_workers())) {
        const std::vector<int> stragglers =
            round.Update(version, now, svc.sync_round_timeout_s(), live_slots,
                         assembler.MissingSlots(version, live_slots));
        for (int slot : stragglers) {
          d_.metrics->Add("juggle_sync_round_stragglers_total", 1);
          std::printf("worker slot %d sent nothing for policy version %ld within %.0f s; "
                      "training goes on without it until it does\n",
                      slot, static_cast<long>(version), svc.sync_round_timeout_s());
        }
        batch = assembler.TakeSync(version, round.Required(live_slots), &dropped);
      }
      if (!batch && d_.dashboard != nullptr) {
        d_.dashboard->SetWaitingFor(assembler.MissingSlots(version, live_slots),
                                    static_cast<int>(d_.queue->size()));
      }
    } else {
      const int wanted = svc.unrolls_per_iteration() > 0 ? svc.unrolls_per_iteration() : live_envs;
      if (wanted > 0) batch = assembler.TakeAsync(version, svc.max_policy_lag(), wanted, &dropped);
    }
    dropped += assembler.DropPartialsOlderThan(svc.synchronous() ? version
                                                                 : version - svc.max_policy_lag());
    if (dropped) d_.metrics->Add("juggle_unrolls_dropped_total", dropped, {{"reason", "stale"}});
    if (assembler.evicted_unrolls() > evicted_reported) {
      d_.metrics->Add("juggle_unrolls_dropped_total",
                      static_cast<double>(assembler.evicted_unrolls() - evicted_reported),
                      {{"reason", "overflow"}});
      evicted_reported = assembler.evicted_unrolls();
    }
    if (assembler.ignored_unrolls() > ignored_reported) {
      d_.metrics->Add("juggle_unrolls_dropped_total",
                      static_cast<double>(assembler.ignored_unrolls() - ignored_reported),
                      {{"reason", "duplicate"}});
      ignored_reported = assembler.ignored_unrolls();
    }
    d_.metrics->Set("juggle_unrolls_held", static_cast<double>(assembler.held_unrolls()));
    d_.metrics->Set("juggle_unrolls_partial", static_cast<double>(assembler.partial_unrolls()));
    if (!batch) continue;

    // Update. The events were validated against the graph by DecodeChunk.
    const auto t_update = Clock::now();
    phase(LoopPhase::kUpdating);
    if (svc.adaptive_walk()) {
      for (const EdgeEvent& e : batch->events) d_.walk->Apply(e).IgnoreError();
    }
    double lag_sum = 0;
    for (int64_t v : batch->batch.policy_version) {
      d_.metrics->Observe("juggle_policy_lag_versions", static_cast<double>(version - v));
      lag_sum += version - v;
    }
    absl::StatusOr<UpdateStats> update =
        d_.trainer->Update(batch->batch, svc.synchronous() ? 0 : svc.max_policy_lag());
    if (!update.ok()) {
      d_.metrics->Add("juggle_unrolls_dropped_total", batch->batch.num_unrolls, {{"reason", "update"}});
      std::fprintf(stderr, "warning: batch rejected by the trainer: %s\n",
                   std::string(update.status().message()).c_str());
      phase(LoopPhase::kWaitingForData);
      continue;
    }
    d_.publish_snapshot();
    d_.metrics->Add("juggle_unrolls_trained_total", batch->batch.num_unrolls);
    const auto t_end = Clock::now();

    // Report.
    IterationReport r;
    r.iteration = d_.trainer->iteration();
    r.samples = batch->batch.num_samples();
    r.iteration_s = Seconds(t_end - last_end);
    d_.progress->samples += r.samples;
    d_.progress->train_seconds += r.iteration_s;
    r.total_samples = d_.progress->samples;
    r.train_seconds = d_.progress->train_seconds;
    r.wait_s = Seconds(t_update - last_end);
    r.update_s = Seconds(t_end - t_update);
    r.samples_per_s = r.samples / std::max(r.iteration_s, 1e-9);
    r.sim_s_per_s = r.samples_per_s * d_.control_dt;
    const EpisodeCounters& ep = batch->stats;
    r.episodes = ep.episodes;
    r.mean_return = ep.mean_return();
    r.mean_episode_len = ep.mean_length();
    r.completions_per_episode = ep.mean_completions();
    r.juggles_per_episode = ep.mean_juggles();
    r.mean_policy_lag = batch->batch.num_unrolls ? lag_sum / batch->batch.num_unrolls : 0;
    r.workers = static_cast<int>(live.size());
    r.value_loss = update->value_loss;
    r.approx_kl = update->approx_kl;
    r.actor_lr = update->actor_lr;
    r.latest_eval = latest_eval;
    r.policy_version = d_.trainer->version();
    r.queue_depth = static_cast<int>(d_.queue->size());
    r.outcomes = OutcomeCounts(ep, d_.outcome_names);
    GateStatisticsOfBatch(*d_.trainer, batch->batch, d_.gate_sample_rows, &r);
    last_end = t_end;
    RecordIteration(r, d_.metrics);
    if (!d_.edge_labels.empty()) {
      WalkEventTotals delta;
      delta.Resize(static_cast<int>(d_.edge_labels.size()));
      for (const EdgeEvent& e : batch->events) delta.Add(e);
      RecordWalk(d_.edge_labels, d_.walk->counts(), delta.chosen, delta.completed, delta.failed,
                 d_.metrics);
    }
    if (d_.dashboard != nullptr) {
      d_.dashboard->RecordIteration(r, batch->events, d_.walk->counts(), r.policy_version);
    }
    if (d_.on_iteration) d_.on_iteration(r);
    if (d_.evaluator != nullptr && d_.evaluator->enabled() &&
        d_.evaluator->Due(r.iteration, d_.progress->train_seconds)) {
      // The evaluation's wall time counts as training time (it is part of the run) but not
      // as the next iteration's.
      const auto t_eval = Clock::now();
      phase(LoopPhase::kEvaluating);
      absl::StatusOr<EigenPolicy> policy = EigenPolicy::Create(
          *d_.model, d_.trainer->ExportPolicy(), d_.obs_dim, d_.act_dim);
      if (policy.ok()) {
        InRunEvaluation e = d_.evaluator->Run(*policy, r.iteration, d_.progress->samples,
                                              d_.progress->train_seconds);
        const double spent = Seconds(Clock::now() - t_eval);
        d_.progress->train_seconds += spent;
        e.train_seconds = d_.progress->train_seconds;
        latest_eval = e.ToShort();
        RecordEvaluation(e.summary, d_.metrics);
        if (d_.dashboard != nullptr) d_.dashboard->RecordEvaluation(e);
        if (d_.on_eval) d_.on_eval(e);
      }
      last_end = Clock::now();
    }
    if (svc.checkpoint_every() > 0 && r.iteration % svc.checkpoint_every() == 0) {
      if (absl::Status s = checkpoint(); !s.ok()) return s;
    }
    phase(LoopPhase::kWaitingForData);
  }
  // Workers long-polling for a newer policy get the current one at once, not at their deadline.
  d_.release_workers();
  absl::Status saved = checkpoint();
  phase(LoopPhase::kFinished);
  return saved;
}

}  // namespace juggle

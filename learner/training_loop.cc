#include "learner/training_loop.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>

#include "absl/strings/str_cat.h"
#include "common/eigen_policy.h"
#include "learner/imitation_schedule.h"
#include "learner/learner_metrics.h"

namespace juggle {
namespace {

double Seconds(std::chrono::steady_clock::duration d) {
  return std::chrono::duration<double>(d).count();
}

// The actor's gate statistics (paper Eq. 4) on up to `rows` observations of `batch`, taken at
// an even stride; left unset when the actor is not a mixture. Costs one gate forward pass.
void GateStatisticsOfBatch(const PpoTrainer& trainer, const UnrollBatch& batch, int rows,
                           runlog::IterationRecord* r) {
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
  r->set_gate_specialization(stats.specialization);
  r->set_gate_utilization(stats.utilization);
}

}  // namespace

TrainingLoop::TrainingLoop(Deps deps, Limits limits)
    : d_(std::move(deps)),
      limits_(limits),
      // What it may hold per worker: the versions a batch can use, plus one of slack.
      assembler_(d_.service->synchronous() ? 2 : d_.service->max_policy_lag() + 2,
                 d_.service->synchronous() ? 0 : d_.service->unrolls_per_iteration()),
      last_end_(Clock::now()) {
  walk_totals_.Resize(static_cast<int>(d_.walk->counts().size()));
}

template <typename F>
absl::Status TrainingLoop::Tell(F hook) {
  for (TrainingObserver* o : d_.observers) {
    if (absl::Status s = hook(o); !s.ok()) return s;
  }
  return absl::OkStatus();
}

void TrainingLoop::SetPhase(LoopPhase phase, std::vector<int> waiting_for) {
  const PhaseEvent event{phase, std::move(waiting_for), static_cast<int>(d_.queue->size())};
  for (TrainingObserver* o : d_.observers) o->OnPhase(event);
}

absl::Status TrainingLoop::Run(const std::atomic<bool>* stop) {
  const auto start = Clock::now();
  last_end_ = start;
  absl::Status status;
  SetPhase(LoopPhase::kWaitingForData);
  while (status.ok() && !stop->load()) {
    if (limits_.max_iterations > 0 && d_.trainer->iteration() >= limits_.max_iterations) break;
    if (limits_.max_minutes > 0 && Seconds(Clock::now() - start) > limits_.max_minutes * 60) break;
    Ingest();
    const auto now = Clock::now();
    const Live live = TrackWorkers(now);
    const std::optional<Contribution> batch = TakeBatch(live, now);
    if (!batch) continue;

    const auto t_update = Clock::now();
    SetPhase(LoopPhase::kUpdating);
    const absl::StatusOr<UpdateStats> update = Train(*batch);
    if (!update.ok()) {
      SetPhase(LoopPhase::kWaitingForData);
      continue;
    }
    const runlog::IterationRecord record =
        Report(*batch, *update, static_cast<int>(live.workers.size()), t_update, Clock::now());
    WalkEventTotals walk_events;
    walk_events.Resize(static_cast<int>(d_.walk->counts().size()));
    for (const EdgeEvent& e : batch->events) walk_events.Add(e);
    walk_totals_.Add(walk_events);
    const IterationEvent event{record, walk_events, d_.walk->counts()};
    status = Tell([&](TrainingObserver* o) { return o->OnIteration(event); });
    if (status.ok()) status = MaybeEvaluate(record.iteration());
    const int every = d_.service->checkpoint_every();
    if (status.ok() && every > 0 && record.iteration() % every == 0) status = Checkpoint();
    SetPhase(LoopPhase::kWaitingForData);
  }
  // Workers long-polling for a newer policy get the current one at once, not at their deadline.
  d_.release_workers();
  absl::Status saved = Checkpoint();
  SetPhase(LoopPhase::kFinished);
  return status.ok() ? saved : status;
}

void TrainingLoop::Ingest() {
  std::optional<ChunkPart> part = d_.queue->Pop(Clock::now() + std::chrono::milliseconds(100));
  if (!part) return;
  ++*d_.chunks_ingested;
  const int unrolls = part->data.batch.num_unrolls;
  if (d_.discard_data) {
    d_.metrics->Add("juggle_unrolls_dropped_total", unrolls, {{"reason", "discarded"}});
    return;
  }
  if (absl::Status added = assembler_.Add(std::move(*part)); !added.ok()) {
    d_.metrics->Add("juggle_chunks_rejected_total", 1, {{"reason", "inconsistent_parts"}});
    d_.metrics->Add("juggle_unrolls_dropped_total", unrolls, {{"reason", "inconsistent_parts"}});
    std::fprintf(stderr, "warning: %s\n", std::string(added.message()).c_str());
  }
}

TrainingLoop::Live TrainingLoop::TrackWorkers(Clock::time_point now) {
  d_.metrics->Set("juggle_ingest_queue_chunks", static_cast<double>(d_.queue->size()));
  const auto timeout = std::chrono::duration<double>(d_.service->worker_timeout_s());
  for (uint64_t dead : d_.registry->Expire(now, timeout)) {
    d_.metrics->Add("juggle_worker_timeouts_total", 1);
    std::printf("worker incarnation %lx timed out; its partial data is discarded\n",
                static_cast<unsigned long>(dead));
  }
  Live live;
  live.workers = d_.registry->Live();
  std::vector<uint64_t> incarnations;
  for (const WorkerInfo& w : live.workers) {
    incarnations.push_back(w.incarnation);
    live.slots.push_back(w.slot);
    live.envs += w.num_envs;
  }
  const int64_t partial_before = assembler_.partial_unrolls();
  assembler_.DropAllBut(incarnations);
  if (const int64_t gone = partial_before - assembler_.partial_unrolls(); gone > 0) {
    d_.metrics->Add("juggle_unrolls_dropped_total", static_cast<double>(gone),
                    {{"reason", "worker_gone"}});
  }
  RecordWorkers(live.workers, now, &reported_slots_, d_.metrics);
  return live;
}

std::optional<Contribution> TrainingLoop::TakeBatch(const Live& live, Clock::time_point now) {
  const config::ServiceConfig& svc = *d_.service;
  const int64_t version = d_.trainer->version();
  int64_t dropped = 0;
  std::optional<Contribution> batch;
  if (svc.synchronous()) {
    if (static_cast<int>(live.workers.size()) >= std::max(1, svc.min_workers())) {
      std::map<int, int64_t> newest_sent;
      for (const WorkerInfo& w : live.workers) newest_sent[w.slot] = w.newest_chunk_version;
      const std::vector<int> stragglers =
          round_.Update(version, now, svc.sync_round_timeout_s(), live.slots,
                        assembler_.MissingSlots(version, live.slots), newest_sent);
      for (int slot : stragglers) {
        d_.metrics->Add("juggle_sync_round_stragglers_total", 1);
        std::printf("worker slot %d sent nothing for policy version %ld within %.0f s; "
                    "training goes on without it until it does\n",
                    slot, static_cast<long>(version), svc.sync_round_timeout_s());
      }
      batch = assembler_.TakeSync(version, round_.Required(live.slots), &dropped);
    }
    if (!batch) {
      SetPhase(LoopPhase::kWaitingForData, assembler_.MissingSlots(version, live.slots));
    }
  } else {
    const int wanted = svc.unrolls_per_iteration() > 0 ? svc.unrolls_per_iteration() : live.envs;
    if (wanted > 0) batch = assembler_.TakeAsync(version, svc.max_policy_lag(), wanted, &dropped);
  }
  dropped += assembler_.DropPartialsOlderThan(svc.synchronous() ? version
                                                                : version - svc.max_policy_lag());
  AccountDrops(dropped);
  return batch;
}

void TrainingLoop::AccountDrops(int64_t stale) {
  Metrics& m = *d_.metrics;
  if (stale) m.Add("juggle_unrolls_dropped_total", stale, {{"reason", "stale"}});
  if (assembler_.evicted_unrolls() > evicted_reported_) {
    m.Add("juggle_unrolls_dropped_total",
          static_cast<double>(assembler_.evicted_unrolls() - evicted_reported_),
          {{"reason", "overflow"}});
    evicted_reported_ = assembler_.evicted_unrolls();
  }
  if (assembler_.ignored_unrolls() > ignored_reported_) {
    m.Add("juggle_unrolls_dropped_total",
          static_cast<double>(assembler_.ignored_unrolls() - ignored_reported_),
          {{"reason", "duplicate"}});
    ignored_reported_ = assembler_.ignored_unrolls();
  }
  m.Set("juggle_unrolls_held", static_cast<double>(assembler_.held_unrolls()));
  m.Set("juggle_unrolls_partial", static_cast<double>(assembler_.partial_unrolls()));
}

absl::StatusOr<UpdateStats> TrainingLoop::Train(const Contribution& batch) {
  // The events were validated against the graph by DecodeChunk.
  if (d_.service->adaptive_walk()) {
    for (const EdgeEvent& e : batch.events) d_.walk->Apply(e).IgnoreError();
  }
  const int64_t version = d_.trainer->version();
  double lag_sum = 0;
  for (int64_t v : batch.batch.policy_version) {
    d_.metrics->Observe("juggle_policy_lag_versions", static_cast<double>(version - v));
    lag_sum += static_cast<double>(version - v);
  }
  batch_lag_ = batch.batch.num_unrolls ? lag_sum / batch.batch.num_unrolls : 0;
  // Labels go to the demonstrations; expert-driven unrolls never reach PPO.
  const UnrollBatch* ppo_batch = &batch.batch;
  UnrollBatch student_only;
  batch_labelled_ = 0;
  std::optional<DemoBuffer> fresh;  // this batch's labels alone (held-out for the error below)
  if (batch.batch.has_labels()) {
    batch_labelled_ = int64_t(batch.batch.num_labelled()) * batch.batch.unroll_length;
    if (d_.demos != nullptr) {
      fresh.emplace(batch_labelled_, d_.demos->obs_dim(), d_.demos->act_dim());
      fresh->AddLabelled(batch.batch);
      d_.metrics->Add("juggle_demo_labels_total", d_.demos->AddLabelled(batch.batch));
    }
    student_only = WithoutExpertUnrolls(batch.batch);
    expert_samples_ += batch.batch.num_samples() - student_only.num_samples();
    ppo_batch = &student_only;
  }
  const ImitationTerm imitation =
      d_.imitation ? ImitationFor(*d_.imitation, d_.trainer->iteration(), d_.demos) : ImitationTerm();
  // The policy that collected the fresh labels, before it trains on them.
  if (fresh) fresh_error_ = d_.trainer->ImitationError(*fresh, imitation.action_weights);
  absl::StatusOr<UpdateStats> update = d_.trainer->Update(
      *ppo_batch, d_.service->synchronous() ? 0 : d_.service->max_policy_lag(), imitation);
  if (!update.ok()) {
    d_.metrics->Add("juggle_unrolls_dropped_total", batch.batch.num_unrolls,
                    {{"reason", "update"}});
    std::fprintf(stderr, "warning: batch rejected by the trainer: %s\n",
                 std::string(update.status().message()).c_str());
    return update;
  }
  d_.publish_snapshot();
  d_.metrics->Add("juggle_unrolls_trained_total", batch.batch.num_unrolls);
  return update;
}

runlog::IterationRecord TrainingLoop::Report(const Contribution& batch, const UpdateStats& update,
                                             int workers, Clock::time_point t_update,
                                             Clock::time_point t_end) {
  const int64_t samples = batch.batch.num_samples();
  const double iteration_s = Seconds(t_end - last_end_);
  d_.progress->samples += samples;
  d_.progress->train_seconds += iteration_s;
  runlog::IterationRecord r;
  r.set_iteration(static_cast<int32_t>(d_.trainer->iteration()));
  r.set_iteration_samples(static_cast<int32_t>(samples));
  r.set_samples(static_cast<double>(d_.progress->samples));
  r.set_train_s(d_.progress->train_seconds);
  r.set_iteration_s(iteration_s);
  r.set_wait_s(Seconds(t_update - last_end_));
  r.set_update_s(Seconds(t_end - t_update));
  r.set_samples_per_s(samples / std::max(iteration_s, 1e-9));
  r.set_sim_s_per_s(r.samples_per_s() * d_.control_dt);
  const EpisodeCounters& ep = batch.stats;
  r.set_episodes(static_cast<int32_t>(ep.episodes));
  r.set_mean_return(ep.mean_return());
  r.set_mean_episode_len(ep.mean_length());
  r.set_completions_per_episode(ep.mean_completions());
  r.set_juggles_per_episode(ep.mean_juggles());
  r.set_policy_lag(batch_lag_);
  r.set_workers(workers);
  r.set_value_loss(update.value_loss);
  r.set_approx_kl(update.approx_kl);
  r.set_actor_lr(update.actor_lr);
  r.set_policy_version(static_cast<int32_t>(d_.trainer->version()));
  r.set_queue_depth(static_cast<int32_t>(d_.queue->size()));
  SetOutcomeCounts(ep, d_.outcome_names, r.mutable_outcomes());
  r.set_cloning_only(update.cloned_only);
  r.set_imitation_loss(update.imitation_loss);
  r.set_imitation_fresh_error(fresh_error_);
  r.set_imitation_weight(update.imitation_weight);
  r.set_labelled_share(samples ? double(batch_labelled_) / samples : 0);
  r.set_demo_buffer(d_.demos ? static_cast<double>(d_.demos->size()) : 0);
  r.set_expert_episodes(static_cast<int32_t>(batch.expert_stats.episodes));
  r.set_expert_juggles_per_episode(batch.expert_stats.mean_juggles());
  r.set_expert_samples(static_cast<double>(expert_samples_));
  const ExpertCounters& cost = batch.expert_cost;
  r.set_expert_labels(static_cast<double>(cost.labels));
  r.set_expert_replans(static_cast<double>(cost.replans));
  r.set_expert_rollout_steps(static_cast<double>(cost.rollout_steps));
  r.set_expert_rescues(static_cast<double>(cost.rescues));
  r.set_expert_proposal_tried(static_cast<double>(cost.proposal_tried));
  r.set_expert_proposal_chosen(static_cast<double>(cost.proposal_chosen));
  r.set_expert_proposal_weight_sum(cost.proposal_weight_sum);
  GateStatisticsOfBatch(*d_.trainer, batch.batch, d_.gate_sample_rows, &r);
  last_end_ = t_end;
  return r;
}

absl::Status TrainingLoop::MaybeEvaluate(int64_t iteration) {
  if (d_.evaluator == nullptr || !d_.evaluator->enabled() ||
      !d_.evaluator->Due(iteration, d_.progress->train_seconds)) {
    return absl::OkStatus();
  }
  // The evaluation's wall time counts as training time (it is part of the run) but not as the
  // next iteration's.
  const auto t_eval = Clock::now();
  SetPhase(LoopPhase::kEvaluating);
  absl::StatusOr<EigenPolicy> policy =
      EigenPolicy::Create(*d_.model, d_.trainer->ExportPolicy(), d_.obs_dim, d_.act_dim);
  absl::Status status;
  if (policy.ok()) {
    runlog::EvaluationRecord e = d_.evaluator->Run(*policy, iteration, d_.progress->samples,
                                                   d_.progress->train_seconds);
    d_.progress->train_seconds += Seconds(Clock::now() - t_eval);
    e.set_train_s(d_.progress->train_seconds);
    status = Tell([&](TrainingObserver* o) { return o->OnEvaluation(e); });
  }
  last_end_ = Clock::now();
  return status;
}

absl::Status TrainingLoop::Checkpoint() {
  // The same iteration again (a run that ends on a checkpoint iteration): already saved.
  if (d_.trainer->iteration() == last_checkpoint_iteration_) return absl::OkStatus();
  SetPhase(LoopPhase::kCheckpointing);
  absl::StatusOr<std::string> path = d_.checkpoint();
  SetPhase(LoopPhase::kWaitingForData);
  if (!path.ok()) return path.status();  // the final checkpoint tries again
  last_checkpoint_iteration_ = d_.trainer->iteration();
  runlog::CheckpointRecord record;
  record.set_event("walk");
  record.set_iteration(static_cast<int32_t>(d_.trainer->iteration()));
  record.set_checkpoint(*path);
  record.mutable_weights()->Add(d_.walk->counts().begin(), d_.walk->counts().end());
  record.mutable_chosen()->Add(walk_totals_.chosen.begin(), walk_totals_.chosen.end());
  record.mutable_completed()->Add(walk_totals_.completed.begin(), walk_totals_.completed.end());
  record.mutable_failed()->Add(walk_totals_.failed.begin(), walk_totals_.failed.end());
  return Tell([&](TrainingObserver* o) { return o->OnCheckpoint(record); });
}

}  // namespace juggle

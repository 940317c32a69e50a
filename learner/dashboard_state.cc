#include "learner/dashboard_state.h"

#include <algorithm>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_join.h"
#include "envs/registry.h"
#include "proto/control_graph.pb.h"

namespace juggle {
namespace {

double Seconds(std::chrono::steady_clock::duration d) {
  return std::chrono::duration<double>(d).count();
}

std::string StageName(config::Stage stage) {
  std::string name = config::Stage_Name(stage);
  if (name.rfind("STAGE_", 0) == 0) name = name.substr(6);
  return name;
}

// Keeps the entries whose sequence is a multiple of `stride`.
template <typename T>
void Thin(std::vector<std::pair<int64_t, T>>* entries, int64_t stride) {
  entries->erase(std::remove_if(entries->begin(), entries->end(),
                                [stride](const auto& e) { return e.first % stride != 0; }),
                 entries->end());
}

}  // namespace

void DescribeGraph(const ControlGraph& graph, DashboardRunInfo* info) {
  info->nodes.clear();
  info->edges.clear();
  for (int n = 0; n < graph.num_nodes(); ++n) {
    const GraphNode& node = graph.node(n);
    info->nodes.push_back({node.name, StageName(node.stage), node.initial});
  }
  for (int e = 0; e < graph.num_edges(); ++e) {
    const GraphEdge& edge = graph.edge(e);
    info->edges.push_back({edge.from, edge.to, edge.base_weight});
  }
}

DashboardRunInfo DescribeRun(const LoadedConfig& config, const EnvSpec& spec) {
  const config::RunConfig& run = config.run;
  DashboardRunInfo info;
  info.config_name = run.name();
  info.config_path = config.config_path;
  absl::StatusOr<const EnvFamily*> family = FamilyOf(run);
  if (family.ok()) info.family = std::string((*family)->name());
  info.seed = run.seed();
  info.synchronous = run.service().synchronous();
  info.min_workers = run.service().min_workers();
  info.max_policy_lag = info.synchronous ? 0 : run.service().max_policy_lag();
  info.queue_capacity = std::max(1, run.service().queue_capacity());
  info.checkpoint_every = run.service().checkpoint_every();
  info.worker_timeout_s = run.service().worker_timeout_s();
  info.control_dt = spec.control_dt();
  info.outcome_names = spec.outcome_names();
  DescribeGraph(spec.graph(), &info);
  return info;
}

runlog::RunRecord RunRecordOf(const DashboardRunInfo& info, double started_unix) {
  runlog::RunRecord r;
  r.set_event("run");
  r.set_config(info.config_name);
  r.set_config_path(info.config_path);
  r.set_family(info.family);
  r.set_seed(info.seed);
  r.set_mode(info.synchronous ? "synchronous" : "asynchronous");
  r.set_min_workers(info.min_workers);
  r.set_max_policy_lag(info.max_policy_lag);
  r.set_queue_capacity(info.queue_capacity);
  r.set_checkpoint_every(info.checkpoint_every);
  r.set_worker_timeout_s(info.worker_timeout_s);
  r.set_control_dt(info.control_dt);
  for (const std::string& name : info.outcome_names) r.add_outcome_names(name);
  for (const DashboardRunInfo::Node& n : info.nodes) {
    runlog::RunRecord::Node* node = r.add_nodes();
    node->set_name(n.name);
    node->set_stage(n.stage);
    node->set_initial(n.initial);
  }
  for (const DashboardRunInfo::Edge& e : info.edges) {
    runlog::RunRecord::Edge* edge = r.add_edges();
    edge->set_from(e.from);
    edge->set_to(e.to);
    edge->set_w0(e.base_weight);
  }
  r.set_started_unix(started_unix);
  return r;
}

DashboardRunInfo RunInfoOf(const runlog::RunRecord& r) {
  DashboardRunInfo info;
  info.config_name = r.config();
  info.config_path = r.config_path();
  info.family = r.family();
  info.seed = r.seed();
  info.synchronous = r.mode() != "asynchronous";
  info.min_workers = r.min_workers();
  info.max_policy_lag = r.max_policy_lag();
  info.queue_capacity = r.queue_capacity();
  info.checkpoint_every = r.checkpoint_every();
  info.worker_timeout_s = r.worker_timeout_s();
  info.control_dt = r.control_dt();
  info.outcome_names.assign(r.outcome_names().begin(), r.outcome_names().end());
  for (const runlog::RunRecord::Node& n : r.nodes()) {
    info.nodes.push_back({n.name(), n.stage(), n.initial()});
  }
  const int num_nodes = static_cast<int>(info.nodes.size());
  for (const runlog::RunRecord::Edge& e : r.edges()) {
    // Edges between unknown nodes (a damaged record) are left out.
    if (e.from() < 0 || e.to() < 0 || e.from() >= num_nodes || e.to() >= num_nodes) continue;
    info.edges.push_back({e.from(), e.to(), e.w0()});
  }
  return info;
}

RunState DecideRunState(const RunStateInputs& in) {
  switch (in.phase) {
    case LoopPhase::kStarting:
      return {"starting", "the learner is up; training has not begun"};
    case LoopPhase::kFinished:
      return {"finished", "training ended (limit reached or stopped); the last checkpoint is written"};
    case LoopPhase::kEvaluating:
      return {"evaluating", absl::StrCat("in-run evaluation running for ",
                                         static_cast<int>(in.phase_seconds), " s")};
    case LoopPhase::kCheckpointing:
      return {"checkpointing", "writing a checkpoint"};
    case LoopPhase::kWaitingForData:
    case LoopPhase::kUpdating:
      break;
  }
  if (in.live_workers < in.needed_workers) {
    return {"waiting for workers",
            absl::StrCat(in.live_workers, " live worker(s); ",
                         in.synchronous ? "synchronous mode needs " : "training needs ",
                         in.needed_workers)};
  }
  const double limit = std::max(kStallFloorSeconds, 10 * in.typical_iteration_s);
  if (in.phase == LoopPhase::kWaitingForData && in.seconds_since_progress > limit) {
    std::string reason = absl::StrCat("no iteration for ", static_cast<int>(in.seconds_since_progress),
                                      " s");
    if (in.synchronous && !in.waiting_for_slots.empty()) {
      absl::StrAppend(&reason, "; waiting for version ", in.version, " data from slot(s) ",
                      absl::StrJoin(in.waiting_for_slots, ", "));
    } else if (!in.synchronous) {
      absl::StrAppend(&reason, "; not enough fresh unrolls arrived");
    }
    absl::StrAppend(&reason, "; queue ", in.queue_depth, "/", in.queue_capacity);
    return {"stalled", reason};
  }
  return {"training", ""};
}

DashboardState::DashboardState(DashboardRunInfo info, int capacity)
    : info_(std::move(info)),
      capacity_(std::max(2, capacity)),
      start_(Clock::now()),
      phase_since_(start_),
      last_progress_(start_) {
  edge_counts_.reserve(info_.edges.size());
  for (const DashboardRunInfo::Edge& e : info_.edges) edge_counts_.push_back(e.base_weight);
  totals_.Resize(static_cast<int>(info_.edges.size()));
}

void DashboardState::OnPhase(const PhaseEvent& event) {
  std::lock_guard<std::mutex> lock(mu_);
  if (event.phase == LoopPhase::kWaitingForData) {
    waiting_for_ = event.waiting_for_slots;
    queue_depth_ = event.queue_depth;
  }
  if (event.phase == phase_) return;
  if (phase_ == LoopPhase::kStarting) last_progress_ = Clock::now();
  phase_ = event.phase;
  phase_since_ = Clock::now();
}

void DashboardState::SetInitial(const std::vector<double>& edge_counts, int64_t version,
                                int64_t total_samples, double train_seconds) {
  std::lock_guard<std::mutex> lock(mu_);
  edge_counts_ = edge_counts;
  version_ = version;
  total_samples_ = total_samples;
  train_seconds_ = train_seconds;
}

absl::Status DashboardState::OnIteration(const IterationEvent& event) {
  const runlog::IterationRecord& report = event.record;
  WalkEventTotals delta;
  delta.Resize(static_cast<int>(info_.edges.size()));
  delta.Add(event.walk_events);
  std::lock_guard<std::mutex> lock(mu_);
  last_iteration_ = Clock::now();
  last_progress_ = *last_iteration_;
  version_ = report.policy_version();
  total_samples_ = static_cast<int64_t>(report.samples());
  train_seconds_ = report.train_s();
  latest_ = report;
  recent_iteration_s_.push_back(report.iteration_s());
  if (recent_iteration_s_.size() > 10) recent_iteration_s_.pop_front();
  ++sequence_;
  if (sequence_ % stride_ == 0) points_.emplace_back(sequence_, report);
  if (static_cast<int>(points_.size()) > capacity_) {
    stride_ *= 2;
    Thin(&points_, stride_);
  }
  if (event.edge_counts.size() == info_.edges.size()) edge_counts_ = event.edge_counts;
  totals_.Add(delta);
  recent_.push_back(std::move(delta));
  if (static_cast<int>(recent_.size()) > kRecentIterations) recent_.pop_front();
  return absl::OkStatus();
}

absl::Status DashboardState::OnEvaluation(const runlog::EvaluationRecord& evaluation) {
  std::lock_guard<std::mutex> lock(mu_);
  latest_evaluation_ = evaluation;
  ++evaluation_sequence_;
  if (evaluation_sequence_ % evaluation_stride_ == 0) {
    evaluations_.emplace_back(evaluation_sequence_, evaluation);
  }
  if (static_cast<int>(evaluations_.size()) > kEvaluationCapacity) {
    evaluation_stride_ *= 2;
    Thin(&evaluations_, evaluation_stride_);
  }
  return absl::OkStatus();
}

absl::Status DashboardState::OnCheckpoint(const runlog::CheckpointRecord& record) {
  const size_t n = info_.edges.size();
  std::lock_guard<std::mutex> lock(mu_);
  last_checkpoint_ = Clock::now();
  if (record.weights_size() == static_cast<int>(n)) {
    edge_counts_.assign(record.weights().begin(), record.weights().end());
  }
  if (record.chosen_size() == static_cast<int>(n) && record.completed_size() == static_cast<int>(n) &&
      record.failed_size() == static_cast<int>(n)) {
    for (size_t e = 0; e < n; ++e) {
      totals_.chosen[e] = static_cast<int64_t>(record.chosen(e));
      totals_.completed[e] = static_cast<int64_t>(record.completed(e));
      totals_.failed[e] = static_cast<int64_t>(record.failed(e));
    }
  }
  return absl::OkStatus();
}

DashboardState::History DashboardState::HistorySince(int64_t since, int64_t stride) const {
  std::lock_guard<std::mutex> lock(mu_);
  History h;
  h.stride = stride_;
  h.last_sequence = sequence_;
  const bool incremental = stride == stride_;
  for (const auto& [sequence, report] : points_) {
    if (incremental && sequence <= since) continue;
    h.sequences.push_back(sequence);
    h.points.push_back(report);
  }
  return h;
}

std::vector<runlog::EvaluationRecord> DashboardState::Evaluations() const {
  std::lock_guard<std::mutex> lock(mu_);
  std::vector<runlog::EvaluationRecord> out;
  out.reserve(evaluations_.size() + 1);
  for (const auto& [sequence, e] : evaluations_) out.push_back(e);
  // The newest evaluation is always shown, even between thinned entries.
  if (latest_evaluation_ && (evaluations_.empty() || evaluations_.back().first != evaluation_sequence_)) {
    out.push_back(*latest_evaluation_);
  }
  return out;
}

DashboardState::Snapshot DashboardState::Take() const {
  const Clock::time_point now = Clock::now();
  std::lock_guard<std::mutex> lock(mu_);
  Snapshot s;
  s.phase = phase_;
  s.phase_seconds = Seconds(now - phase_since_);
  s.uptime_s = Seconds(now - start_);
  if (last_checkpoint_) s.checkpoint_age_s = Seconds(now - *last_checkpoint_);
  if (last_iteration_) s.iteration_age_s = Seconds(now - *last_iteration_);
  s.seconds_since_progress = Seconds(now - last_progress_);
  if (!recent_iteration_s_.empty()) {
    std::vector<double> sorted(recent_iteration_s_.begin(), recent_iteration_s_.end());
    std::sort(sorted.begin(), sorted.end());
    s.typical_iteration_s = sorted[sorted.size() / 2];
  }
  s.version = version_;
  s.total_samples = total_samples_;
  s.train_seconds = train_seconds_;
  s.latest = latest_;
  s.latest_evaluation = latest_evaluation_;
  s.edge_counts = edge_counts_;
  s.totals = totals_;
  s.recent.Resize(static_cast<int>(info_.edges.size()));
  for (const WalkEventTotals& r : recent_) s.recent.Add(r);
  s.waiting_for_slots = waiting_for_;
  s.queue_depth = queue_depth_;
  return s;
}

}  // namespace juggle

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

void WalkEventTotals::Resize(int num_edges) {
  chosen.assign(num_edges, 0);
  completed.assign(num_edges, 0);
  failed.assign(num_edges, 0);
}

void WalkEventTotals::Add(const EdgeEvent& e) {
  if (e.edge < 0 || e.edge >= static_cast<int>(chosen.size())) return;
  switch (e.type) {
    case EdgeEventType::kChosen: ++chosen[e.edge]; break;
    case EdgeEventType::kCompleted: ++completed[e.edge]; break;
    case EdgeEventType::kFailed: ++failed[e.edge]; break;
  }
}

void WalkEventTotals::Add(const WalkEventTotals& o) {
  for (size_t i = 0; i < chosen.size() && i < o.chosen.size(); ++i) {
    chosen[i] += o.chosen[i];
    completed[i] += o.completed[i];
    failed[i] += o.failed[i];
  }
}

int64_t WalkEventTotals::events() const {
  int64_t n = 0;
  for (size_t i = 0; i < chosen.size(); ++i) n += chosen[i] + completed[i] + failed[i];
  return n;
}

const char* PhaseName(LoopPhase phase) {
  switch (phase) {
    case LoopPhase::kStarting: return "starting";
    case LoopPhase::kWaitingForData: return "waiting for data";
    case LoopPhase::kUpdating: return "updating";
    case LoopPhase::kEvaluating: return "evaluating";
    case LoopPhase::kCheckpointing: return "checkpointing";
    case LoopPhase::kFinished: return "finished";
  }
  return "unknown";
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

void DashboardState::SetPhase(LoopPhase phase) {
  std::lock_guard<std::mutex> lock(mu_);
  if (phase == phase_) return;
  if (phase_ == LoopPhase::kStarting) last_progress_ = Clock::now();
  phase_ = phase;
  phase_since_ = Clock::now();
}

void DashboardState::SetWaitingFor(std::vector<int> slots, int queue_depth) {
  std::lock_guard<std::mutex> lock(mu_);
  waiting_for_ = std::move(slots);
  queue_depth_ = queue_depth;
}

void DashboardState::SetInitial(const std::vector<double>& edge_counts, int64_t version,
                                int64_t total_samples, double train_seconds) {
  std::lock_guard<std::mutex> lock(mu_);
  edge_counts_ = edge_counts;
  version_ = version;
  total_samples_ = total_samples;
  train_seconds_ = train_seconds;
}

void DashboardState::RecordIteration(const IterationReport& report,
                                     const std::vector<EdgeEvent>& events,
                                     const std::vector<double>& edge_counts, int64_t version) {
  WalkEventTotals delta;
  delta.Resize(static_cast<int>(info_.edges.size()));
  for (const EdgeEvent& e : events) delta.Add(e);
  std::lock_guard<std::mutex> lock(mu_);
  last_iteration_ = Clock::now();
  last_progress_ = *last_iteration_;
  version_ = version;
  total_samples_ = report.total_samples;
  train_seconds_ = report.train_seconds;
  latest_ = report;
  recent_iteration_s_.push_back(report.iteration_s);
  if (recent_iteration_s_.size() > 10) recent_iteration_s_.pop_front();
  ++sequence_;
  if (sequence_ % stride_ == 0) points_.emplace_back(sequence_, report);
  if (static_cast<int>(points_.size()) > capacity_) {
    stride_ *= 2;
    Thin(&points_, stride_);
  }
  edge_counts_ = edge_counts;
  totals_.Add(delta);
  recent_.push_back(std::move(delta));
  if (static_cast<int>(recent_.size()) > kRecentIterations) recent_.pop_front();
}

void DashboardState::RecordEvaluation(const InRunEvaluation& evaluation) {
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
}

void DashboardState::RecordCheckpoint() {
  std::lock_guard<std::mutex> lock(mu_);
  last_checkpoint_ = Clock::now();
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

std::vector<InRunEvaluation> DashboardState::Evaluations() const {
  std::lock_guard<std::mutex> lock(mu_);
  std::vector<InRunEvaluation> out;
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

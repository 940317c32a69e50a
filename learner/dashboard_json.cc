#include "learner/dashboard_json.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "learner/run_log.h"
#include "nlohmann/json.hpp"

namespace juggle {
namespace {

using Json = nlohmann::ordered_json;

constexpr double kSilentHeartbeatSeconds = 3;  // workers beat every second

std::string Dump(const Json& j) {
  // Non-finite numbers become null; invalid UTF-8 (a host name) is replaced, never thrown.
  return j.dump(-1, ' ', false, Json::error_handler_t::replace);
}

Json Optional(const std::optional<double>& v) { return v ? Json(*v) : Json(nullptr); }

// completed / (completed + failed), or null when neither happened.
Json SuccessRate(int64_t completed, int64_t failed) {
  return completed + failed > 0 ? Json(double(completed) / double(completed + failed))
                                : Json(nullptr);
}

// Iteration and evaluation records as in the run log (proto/run_log.proto).
Json RecordToJson(const google::protobuf::Message& record) { return Json::parse(RecordJson(record)); }

Json RunJson(const DashboardRunInfo& info) {
  return {
      {"config", info.config_name},
      {"config_path", info.config_path},
      {"family", info.family},
      {"seed", info.seed},
      {"mode", info.synchronous ? "synchronous" : "asynchronous"},
      {"min_workers", info.min_workers},
      {"max_policy_lag", info.max_policy_lag},
      {"queue_capacity", info.queue_capacity},
      {"checkpoint_every", info.checkpoint_every},
      {"worker_timeout_s", info.worker_timeout_s},
      {"control_dt", info.control_dt},
      {"outcome_names", info.outcome_names},
  };
}

Json GraphJson(const DashboardRunInfo& info, const DashboardState::Snapshot& s) {
  const int num_edges = static_cast<int>(info.edges.size());
  const int num_nodes = static_cast<int>(info.nodes.size());
  auto at = [](const std::vector<int64_t>& v, int i) -> int64_t {
    return i < static_cast<int>(v.size()) ? v[i] : 0;
  };
  std::vector<double> out_weight(num_nodes, 0);
  for (int e = 0; e < num_edges; ++e) {
    const double w = e < static_cast<int>(s.edge_counts.size()) ? s.edge_counts[e]
                                                                 : info.edges[e].base_weight;
    out_weight[info.edges[e].from] += w;
  }
  struct NodeTotals {
    int64_t entered = 0, completed = 0, failed = 0;
    int64_t recent_completed = 0, recent_failed = 0;
  };
  std::vector<NodeTotals> node(num_nodes);
  Json edges = Json::array();
  for (int e = 0; e < num_edges; ++e) {
    const DashboardRunInfo::Edge& edge = info.edges[e];
    const double w = e < static_cast<int>(s.edge_counts.size()) ? s.edge_counts[e]
                                                                 : edge.base_weight;
    NodeTotals& to = node[edge.to];
    to.entered += at(s.totals.chosen, e);
    to.completed += at(s.totals.completed, e);
    to.failed += at(s.totals.failed, e);
    to.recent_completed += at(s.recent.completed, e);
    to.recent_failed += at(s.recent.failed, e);
    edges.push_back({
        {"id", e},
        {"from", edge.from},
        {"to", edge.to},
        {"w0", edge.base_weight},
        {"weight", w},
        {"probability", out_weight[edge.from] > 0 ? w / out_weight[edge.from] : 0.0},
        {"chosen", at(s.totals.chosen, e)},
        {"completed", at(s.totals.completed, e)},
        {"failed", at(s.totals.failed, e)},
        {"success", SuccessRate(at(s.totals.completed, e), at(s.totals.failed, e))},
        {"recent_chosen", at(s.recent.chosen, e)},
        {"recent_success", SuccessRate(at(s.recent.completed, e), at(s.recent.failed, e))},
    });
  }
  Json nodes = Json::array();
  for (int n = 0; n < num_nodes; ++n) {
    const DashboardRunInfo::Node& info_node = info.nodes[n];
    nodes.push_back({
        {"id", n},
        {"name", info_node.name},
        {"stage", info_node.stage},
        {"initial", info_node.initial},
        {"entered", node[n].entered},
        {"completed", node[n].completed},
        {"failed", node[n].failed},
        {"success", SuccessRate(node[n].completed, node[n].failed)},
        {"recent_success", SuccessRate(node[n].recent_completed, node[n].recent_failed)},
    });
  }
  return {{"nodes", std::move(nodes)},
          {"edges", std::move(edges)},
          {"recent_iterations", DashboardState::kRecentIterations}};
}

Json ThroughputJson(const ThroughputView& t) {
  Json rejected = Json::object(), dropped = Json::object();
  for (const auto& [reason, n] : t.rejected) rejected[reason] = n;
  for (const auto& [reason, n] : t.dropped) dropped[reason] = n;
  // Per-bucket (not cumulative) counts, the last bucket above the highest bound.
  Json le = Json::array(), counts = Json::array();
  double below = 0;
  for (size_t i = 0; i < t.policy_lag.upper_bounds.size(); ++i) {
    le.push_back(t.policy_lag.upper_bounds[i]);
    counts.push_back(t.policy_lag.cumulative_counts[i] - below);
    below = t.policy_lag.cumulative_counts[i];
  }
  le.push_back("+Inf");
  counts.push_back(t.policy_lag.count - below);
  return {{"queue_depth", t.queue_depth},
          {"reconnects", t.reconnects},
          {"queue_capacity", t.queue_capacity},
          {"rejected", std::move(rejected)},
          {"dropped", std::move(dropped)},
          {"policy_lag", {{"le", std::move(le)},
                          {"count", std::move(counts)},
                          {"sum", t.policy_lag.sum},
                          {"total", t.policy_lag.count}}}};
}

Json WorkersJson(const std::vector<WorkerView>& workers, int needed) {
  Json rows = Json::array();
  for (const WorkerView& w : workers) {
    rows.push_back({
        {"slot", w.slot},
        {"host", w.host},
        {"incarnation", absl::StrFormat("%x", w.incarnation)},
        {"envs", w.envs},
        {"env_steps_per_s", w.env_steps_per_s},
        {"heartbeat_age_s", w.heartbeat_age_s},
        {"policy_version", w.policy_version},
        {"chunks_accepted", w.chunks_accepted},
        {"chunks_rejected", w.chunks_rejected},
        {"sessions", w.sessions},
        {"status", w.status},
    });
  }
  return {{"live", workers.size()}, {"needed", needed}, {"rows", std::move(rows)}};
}

}  // namespace

std::vector<WorkerView> DescribeWorkers(const std::vector<WorkerInfo>& live,
                                        WorkerRegistry::Clock::time_point now,
                                        const std::vector<int>& waiting_for_slots) {
  std::vector<double> rates;
  for (const WorkerInfo& w : live) rates.push_back(w.env_steps_per_s);
  std::sort(rates.begin(), rates.end());
  const double median = rates.empty() ? 0 : rates[rates.size() / 2];
  std::vector<WorkerView> out;
  for (const WorkerInfo& w : live) {
    WorkerView v;
    v.slot = w.slot;
    v.host = w.host;
    v.incarnation = w.incarnation;
    v.envs = w.num_envs;
    v.env_steps_per_s = w.env_steps_per_s;
    v.heartbeat_age_s = std::chrono::duration<double>(now - w.last_seen).count();
    v.policy_version = w.policy_version;
    v.chunks_accepted = w.chunks_accepted;
    v.chunks_rejected = w.chunks_rejected;
    v.sessions = w.sessions;
    const bool silent = v.heartbeat_age_s >= kSilentHeartbeatSeconds;
    const bool slow = live.size() > 1 && median > 0 && w.env_steps_per_s < 0.5 * median;
    const bool waited_on = std::find(waiting_for_slots.begin(), waiting_for_slots.end(),
                                     w.slot) != waiting_for_slots.end();
    v.status = silent ? "silent" : slow ? "slow" : "ok";
    if (waited_on && (silent || slow)) v.status = "waited on";
    out.push_back(std::move(v));
  }
  return out;
}

ThroughputView DescribeThroughput(const Metrics& metrics, int queue_capacity) {
  ThroughputView t;
  t.queue_depth = static_cast<int>(metrics.Get("juggle_ingest_queue_chunks"));
  t.queue_capacity = queue_capacity;
  for (const auto& [labels, value] : metrics.Series("juggle_worker_reconnects_total")) {
    t.reconnects += value;
  }
  for (const auto& [labels, value] : metrics.Series("juggle_chunks_rejected_total")) {
    auto reason = labels.find("reason");
    t.rejected.emplace_back(reason == labels.end() ? "" : reason->second, value);
  }
  for (const auto& [labels, value] : metrics.Series("juggle_unrolls_dropped_total")) {
    auto reason = labels.find("reason");
    t.dropped.emplace_back(reason == labels.end() ? "" : reason->second, value);
  }
  t.policy_lag = metrics.Histogram("juggle_policy_lag_versions");
  return t;
}

StatusView LiveStatus(const DashboardState& state, const WorkerRegistry& registry,
                      const Metrics& metrics) {
  StatusView v;
  v.live = true;
  v.run = state.info();
  v.snapshot = state.Take();
  const std::vector<WorkerInfo> live = registry.Live();
  v.workers = DescribeWorkers(live, WorkerRegistry::Clock::now(), v.snapshot.waiting_for_slots);
  v.needed_workers = v.run.synchronous ? std::max(1, v.run.min_workers) : 1;
  v.throughput = DescribeThroughput(metrics, v.run.queue_capacity);
  RunStateInputs in;
  in.phase = v.snapshot.phase;
  in.phase_seconds = v.snapshot.phase_seconds;
  in.live_workers = static_cast<int>(live.size());
  in.needed_workers = v.needed_workers;
  in.synchronous = v.run.synchronous;
  in.seconds_since_progress = v.snapshot.seconds_since_progress;
  in.typical_iteration_s = v.snapshot.typical_iteration_s;
  in.version = v.snapshot.version;
  in.waiting_for_slots = v.snapshot.waiting_for_slots;
  in.queue_depth = v.throughput.queue_depth;
  in.queue_capacity = v.throughput.queue_capacity;
  v.state = DecideRunState(in);
  return v;
}

std::string StatusJson(const StatusView& v) {
  const DashboardState::Snapshot& s = v.snapshot;
  Json j = {
      {"schema", 1},
      {"live", v.live},
      {"source", v.source},
      {"generated_unix", UnixNow()},
      {"run", RunJson(v.run)},
      {"state", {{"state", v.state.state},
                 {"reason", v.state.reason},
                 {"phase", PhaseName(s.phase)},
                 {"phase_s", s.phase_seconds}}},
      {"progress", {{"iteration", s.latest ? s.latest->iteration() : 0},
                    {"policy_version", s.version},
                    {"samples", s.total_samples},
                    {"train_s", s.train_seconds},
                    {"uptime_s", v.live ? Json(s.uptime_s) : Json(nullptr)},
                    {"checkpoint_age_s", Optional(s.checkpoint_age_s)},
                    {"iteration_age_s", Optional(s.iteration_age_s)},
                    {"typical_iteration_s", s.typical_iteration_s}}},
      {"latest", s.latest ? RecordToJson(*s.latest) : Json(nullptr)},
      {"throughput", ThroughputJson(v.throughput)},
      {"workers", WorkersJson(v.workers, v.needed_workers)},
      {"graph", GraphJson(v.run, s)},
      {"latest_eval", s.latest_evaluation ? RecordToJson(*s.latest_evaluation) : Json(nullptr)},
  };
  return Dump(j);
}

std::string HistoryJson(const DashboardState::History& h) {
  Json points = Json::array();
  for (size_t i = 0; i < h.points.size(); ++i) {
    Json p = RecordToJson(h.points[i]);
    p["seq"] = h.sequences[i];
    points.push_back(std::move(p));
  }
  return Dump({{"stride", h.stride}, {"last", h.last_sequence}, {"points", std::move(points)}});
}

std::string EvaluationsJson(const std::vector<runlog::EvaluationRecord>& evaluations) {
  Json list = Json::array();
  for (const runlog::EvaluationRecord& e : evaluations) list.push_back(RecordToJson(e));
  return Dump({{"evaluations", std::move(list)}});
}

RecordedDashboard RecordedDashboardOf(const DashboardState& state, const std::string& source,
                                      const std::string& summary) {
  StatusView v;
  v.live = false;
  v.source = source;
  v.run = state.info();
  v.snapshot = state.Take();
  // Ages and waits are of the replay, not of the run.
  v.snapshot.phase = LoopPhase::kFinished;
  v.snapshot.checkpoint_age_s.reset();
  v.snapshot.iteration_age_s.reset();
  v.snapshot.recent.Resize(static_cast<int>(v.run.edges.size()));
  v.state = {"recorded", absl::StrCat("rendered from ", source, " (", summary, ")")};
  v.needed_workers = 0;
  v.throughput.queue_capacity = v.run.queue_capacity;
  RecordedDashboard out;
  out.status = StatusJson(v);
  out.history = HistoryJson(state.HistorySince(0, 0));
  out.evals = EvaluationsJson(state.Evaluations());
  return out;
}

}  // namespace juggle

#include "learner/dashboard_json.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "nlohmann/json.hpp"

namespace juggle {
namespace {

using Json = nlohmann::ordered_json;

constexpr double kSilentHeartbeatSeconds = 3;  // workers beat every second

std::string Dump(const Json& j) {
  // Non-finite numbers become null; invalid UTF-8 (a host name) is replaced, never thrown.
  return j.dump(-1, ' ', false, Json::error_handler_t::replace);
}

double UnixNow() {
  return std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch())
      .count();
}

Json Optional(const std::optional<double>& v) { return v ? Json(*v) : Json(nullptr); }

// completed / (completed + failed), or null when neither happened.
Json SuccessRate(int64_t completed, int64_t failed) {
  return completed + failed > 0 ? Json(double(completed) / double(completed + failed))
                                : Json(nullptr);
}

Json IterationJson(const IterationReport& r) {
  Json j = Json::parse(r.ToJson());
  return j;
}

Json EvaluationJson(const InRunEvaluation& e) { return Json::parse(e.ToJson()); }

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
        {"status", w.status},
    });
  }
  return {{"live", workers.size()}, {"needed", needed}, {"rows", std::move(rows)}};
}

template <typename T>
T Get(const Json& j, const char* key, T fallback) {
  auto it = j.find(key);
  if (it == j.end() || it->is_null()) return fallback;
  try {
    return it->get<T>();
  } catch (const Json::exception&) {
    return fallback;
  }
}

IterationReport IterationFromJson(const Json& j) {
  IterationReport r;
  r.iteration = Get<int64_t>(j, "iteration", 0);
  r.total_samples = Get<int64_t>(j, "samples", 0);
  r.train_seconds = Get<double>(j, "train_s", 0);
  r.samples_per_s = Get<double>(j, "samples_per_s", 0);
  r.sim_s_per_s = Get<double>(j, "sim_s_per_s", 0);
  r.mean_return = Get<double>(j, "mean_return", 0);
  r.mean_episode_len = Get<double>(j, "mean_episode_len", 0);
  r.completions_per_episode = Get<double>(j, "completions_per_episode", 0);
  r.juggles_per_episode = Get<double>(j, "juggles_per_episode", 0);
  r.episodes = Get<int64_t>(j, "episodes", 0);
  r.mean_policy_lag = Get<double>(j, "policy_lag", 0);
  r.iteration_s = Get<double>(j, "iteration_s", 0);
  r.wait_s = Get<double>(j, "wait_s", 0);
  r.update_s = Get<double>(j, "update_s", 0);
  r.workers = Get<int>(j, "workers", 0);
  r.value_loss = Get<double>(j, "value_loss", std::nan(""));
  r.approx_kl = Get<double>(j, "approx_kl", std::nan(""));
  r.actor_lr = Get<double>(j, "actor_lr", 0);
  r.policy_version = Get<int64_t>(j, "policy_version", r.iteration);
  r.queue_depth = Get<int>(j, "queue_depth", 0);
  r.gate_specialization = Get<double>(j, "gate_specialization", -1);
  r.gate_utilization = Get<double>(j, "gate_utilization", -1);
  if (auto o = j.find("outcomes"); o != j.end() && o->is_object()) {
    for (const auto& [name, count] : o->items()) {
      if (count.is_number()) r.outcomes.emplace_back(name, count.get<int64_t>());
    }
  }
  return r;
}

InRunEvaluation EvaluationFromJson(const Json& j) {
  InRunEvaluation e;
  e.iteration = Get<int64_t>(j, "iteration", 0);
  e.samples = Get<int64_t>(j, "samples", 0);
  e.train_seconds = Get<double>(j, "train_s", 0);
  e.eval_seconds = Get<double>(j, "eval_s", 0);
  EvalSummary& s = e.summary;
  s.episodes = Get<int>(j, "episodes", 0);
  s.median_juggles = Get<double>(j, "median_juggles", 0);
  s.p10_juggles = Get<double>(j, "p10_juggles", 0);
  s.p90_juggles = Get<double>(j, "p90_juggles", 0);
  s.mean_juggles = Get<double>(j, "mean_juggles", 0);
  s.frac_juggles_ge_10 = Get<double>(j, "frac_juggles_ge_10", 0);
  s.frac_juggles_ge_20 = Get<double>(j, "frac_juggles_ge_20", 0);
  s.mean_return = Get<double>(j, "mean_return", 0);
  s.mean_episode_s = Get<double>(j, "mean_episode_s", 0);
  if (auto o = j.find("outcomes"); o != j.end() && o->is_object()) {
    for (const auto& [name, count] : o->items()) {
      if (count.is_number()) s.outcomes[name] = count.get<int>();
    }
  }
  e.juggles = Get<std::vector<int>>(j, "juggles", {});
  return e;
}

DashboardRunInfo RunInfoFromJson(const Json& j) {
  DashboardRunInfo info;
  info.config_name = Get<std::string>(j, "config", "");
  info.config_path = Get<std::string>(j, "config_path", "");
  info.family = Get<std::string>(j, "family", "");
  info.seed = Get<uint64_t>(j, "seed", 0);
  info.synchronous = Get<std::string>(j, "mode", "synchronous") == "synchronous";
  info.min_workers = Get<int>(j, "min_workers", 1);
  info.max_policy_lag = Get<int>(j, "max_policy_lag", 0);
  info.queue_capacity = Get<int>(j, "queue_capacity", 0);
  info.checkpoint_every = Get<int>(j, "checkpoint_every", 0);
  info.worker_timeout_s = Get<double>(j, "worker_timeout_s", 10);
  info.control_dt = Get<double>(j, "control_dt", 0);
  info.outcome_names = Get<std::vector<std::string>>(j, "outcome_names", {});
  if (auto nodes = j.find("nodes"); nodes != j.end() && nodes->is_array()) {
    for (const Json& n : *nodes) {
      info.nodes.push_back({Get<std::string>(n, "name", ""), Get<std::string>(n, "stage", ""),
                            Get<bool>(n, "initial", false)});
    }
  }
  if (auto edges = j.find("edges"); edges != j.end() && edges->is_array()) {
    const int num_nodes = static_cast<int>(info.nodes.size());
    for (const Json& e : *edges) {
      DashboardRunInfo::Edge edge{Get<int>(e, "from", -1), Get<int>(e, "to", -1),
                                  Get<double>(e, "w0", 1)};
      if (edge.from < 0 || edge.to < 0 || edge.from >= num_nodes || edge.to >= num_nodes) continue;
      info.edges.push_back(edge);
    }
  }
  return info;
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
      {"progress", {{"iteration", s.latest ? s.latest->iteration : 0},
                    {"policy_version", s.version},
                    {"samples", s.total_samples},
                    {"train_s", s.train_seconds},
                    {"uptime_s", v.live ? Json(s.uptime_s) : Json(nullptr)},
                    {"checkpoint_age_s", Optional(s.checkpoint_age_s)},
                    {"iteration_age_s", Optional(s.iteration_age_s)},
                    {"typical_iteration_s", s.typical_iteration_s}}},
      {"latest", s.latest ? IterationJson(*s.latest) : Json(nullptr)},
      {"throughput", ThroughputJson(v.throughput)},
      {"workers", WorkersJson(v.workers, v.needed_workers)},
      {"graph", GraphJson(v.run, s)},
      {"latest_eval", s.latest_evaluation ? EvaluationJson(*s.latest_evaluation) : Json(nullptr)},
  };
  return Dump(j);
}

std::string HistoryJson(const DashboardState::History& h) {
  Json points = Json::array();
  for (size_t i = 0; i < h.points.size(); ++i) {
    Json p = IterationJson(h.points[i]);
    p["seq"] = h.sequences[i];
    points.push_back(std::move(p));
  }
  return Dump({{"stride", h.stride}, {"last", h.last_sequence}, {"points", std::move(points)}});
}

std::string EvaluationsJson(const std::vector<InRunEvaluation>& evaluations) {
  Json list = Json::array();
  for (const InRunEvaluation& e : evaluations) list.push_back(EvaluationJson(e));
  return Dump({{"evaluations", std::move(list)}});
}

std::string RunRecordJson(const DashboardRunInfo& info) {
  Json j = {{"event", "run"}};
  const Json run = RunJson(info);  // named: items() refers into it
  for (const auto& [key, value] : run.items()) j[key] = value;
  Json nodes = Json::array(), edges = Json::array();
  for (const DashboardRunInfo::Node& n : info.nodes) {
    nodes.push_back({{"name", n.name}, {"stage", n.stage}, {"initial", n.initial}});
  }
  for (const DashboardRunInfo::Edge& e : info.edges) {
    edges.push_back({{"from", e.from}, {"to", e.to}, {"w0", e.base_weight}});
  }
  j["nodes"] = std::move(nodes);
  j["edges"] = std::move(edges);
  j["started_unix"] = UnixNow();
  return Dump(j);
}

std::string WalkRecordJson(int64_t iteration, const std::vector<double>& edge_counts,
                           const WalkEventTotals& totals) {
  return Dump({{"event", "walk"},
               {"iteration", iteration},
               {"weights", edge_counts},
               {"chosen", totals.chosen},
               {"completed", totals.completed},
               {"failed", totals.failed}});
}

absl::StatusOr<MetricsFile> ParseMetricsFile(const std::string& path) {
  std::ifstream in(path);
  if (!in) return absl::NotFoundError(absl::StrCat("cannot read ", path));
  MetricsFile file;
  std::string line;
  int number = 0;
  while (std::getline(in, line)) {
    ++number;
    if (line.find_first_not_of(" \t\r") == std::string::npos) {
      ++file.skipped_lines;
      continue;
    }
    Json j = Json::parse(line, nullptr, /*allow_exceptions=*/false);
    if (j.is_discarded() || !j.is_object()) {
      // A run still being written may end in a partial line: tolerate it only at the end.
      if (in.peek() == std::char_traits<char>::eof()) {
        ++file.skipped_lines;
        break;
      }
      return absl::InvalidArgumentError(absl::StrCat(path, ":", number, ": not a JSON object"));
    }
    const std::string event = Get<std::string>(j, "event", "");
    if (event.empty()) {
      file.iterations.push_back(IterationFromJson(j));
    } else if (event == "eval") {
      file.evaluations.push_back(EvaluationFromJson(j));
    } else if (event == "run") {
      file.run = RunInfoFromJson(j);
      // A resumed run appends a second "run" record; the walk totals restart with it.
      file.walk_iteration.reset();
    } else if (event == "walk") {
      file.walk_iteration = Get<int64_t>(j, "iteration", 0);
      file.edge_counts = Get<std::vector<double>>(j, "weights", {});
      file.walk_totals.chosen = Get<std::vector<int64_t>>(j, "chosen", {});
      file.walk_totals.completed = Get<std::vector<int64_t>>(j, "completed", {});
      file.walk_totals.failed = Get<std::vector<int64_t>>(j, "failed", {});
    } else {
      ++file.skipped_lines;
    }
  }
  return file;
}

RecordedDashboard DashboardFromMetrics(const MetricsFile& file, const std::string& source,
                                       const std::optional<DashboardRunInfo>& info) {
  StatusView v;
  v.live = false;
  v.source = source;
  if (file.run) {
    v.run = *file.run;
  } else if (info) {
    v.run = *info;
  }
  DashboardState::Snapshot& s = v.snapshot;
  s.phase = LoopPhase::kFinished;
  if (!file.iterations.empty()) {
    const IterationReport& last = file.iterations.back();
    s.latest = last;
    s.version = last.policy_version;
    s.total_samples = last.total_samples;
    s.train_seconds = last.train_seconds;
  }
  if (!file.evaluations.empty()) s.latest_evaluation = file.evaluations.back();
  const int num_edges = static_cast<int>(v.run.edges.size());
  s.edge_counts = file.edge_counts;
  if (static_cast<int>(s.edge_counts.size()) != num_edges) {
    s.edge_counts.clear();
    for (const DashboardRunInfo::Edge& e : v.run.edges) s.edge_counts.push_back(e.base_weight);
  }
  s.totals = file.walk_totals;
  if (static_cast<int>(s.totals.chosen.size()) != num_edges) s.totals.Resize(num_edges);
  s.recent.Resize(num_edges);
  v.state = {"recorded",
             absl::StrCat("rendered from ", source, " (", file.iterations.size(),
                          " iterations, ", file.evaluations.size(), " evaluations)")};
  v.needed_workers = 0;
  v.throughput.queue_capacity = v.run.queue_capacity;

  // The whole history, thinned like the live one to at most kDefaultCapacity points.
  DashboardState::History h;
  const int64_t n = static_cast<int64_t>(file.iterations.size());
  h.stride = 1;
  while (n / h.stride > DashboardState::kDefaultCapacity) h.stride *= 2;
  for (int64_t i = 0; i < n; ++i) {
    if ((i + 1) % h.stride != 0 && i + 1 != n) continue;
    h.sequences.push_back(i + 1);
    h.points.push_back(file.iterations[i]);
  }
  h.last_sequence = n;
  RecordedDashboard out;
  out.status = StatusJson(v);
  out.history = HistoryJson(h);
  out.evals = EvaluationsJson(file.evaluations);
  return out;
}

}  // namespace juggle

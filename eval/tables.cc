#include "eval/tables.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <set>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "envs/registry.h"
#include "nlohmann/json.hpp"

namespace juggle {
namespace {

using Json = nlohmann::ordered_json;

// One JSON line; non-finite numbers become null, invalid UTF-8 is replaced.
std::string Line(const Json& j) { return j.dump(-1, ' ', false, Json::error_handler_t::replace); }

}  // namespace

std::vector<NodeRow> NodeTable(const std::vector<EpisodeResult>& episodes,
                               const ControlGraph& graph,
                               const std::vector<std::string>& outcome_names) {
  const int n = std::max(1, graph.num_nodes());
  std::vector<NodeRow> rows(n);
  for (int i = 0; i < n; ++i) rows[i].node = graph.num_nodes() > 0 ? graph.node(i).name : "episode";
  for (const EpisodeResult& e : episodes) {
    for (int i = 0; i < n && i < static_cast<int>(e.node_visits.size()); ++i) {
      rows[i].visits += e.node_visits[i];
      rows[i].completions += e.node_completions[i];
    }
    if (e.outcome != Outcome::kRunning) {
      ++rows[std::clamp(e.end_node, 0, n - 1)].endings[OutcomeName(outcome_names, e.outcome)];
    }
  }
  for (NodeRow& r : rows) {
    r.success_rate = r.visits > 0 ? static_cast<double>(r.completions) / r.visits : 0;
  }
  return rows;
}

std::vector<EdgeRow> EdgeTable(const std::vector<EpisodeResult>& episodes,
                               const ControlGraph& graph) {
  std::vector<EdgeRow> rows(graph.num_edges());
  WalkEventTotals totals;
  totals.Resize(graph.num_edges());
  for (const EpisodeResult& e : episodes) totals.Add(e.edge_events);
  for (int i = 0; i < graph.num_edges(); ++i) {
    rows[i].from = graph.node(graph.edge(i).from).name;
    rows[i].to = graph.node(graph.edge(i).to).name;
    rows[i].chosen = totals.chosen[i];
    rows[i].completed = totals.completed[i];
    rows[i].failed = totals.failed[i];
  }
  return rows;
}

std::string FormatNodeTable(const std::vector<NodeRow>& rows) {
  std::set<std::string> outcomes;
  size_t width = 4;
  for (const NodeRow& r : rows) {
    width = std::max(width, r.node.size());
    for (const auto& [name, count] : r.endings) outcomes.insert(name);
  }
  std::string out = absl::StrFormat("%-*s %8s %11s %8s", static_cast<int>(width), "node", "visits",
                                    "completions", "success");
  for (const std::string& o : outcomes) {
    absl::StrAppend(&out, absl::StrFormat(" %*s", std::max<int>(8, o.size()), o));
  }
  out += "\n";
  for (const NodeRow& r : rows) {
    absl::StrAppend(&out, absl::StrFormat("%-*s %8d %11d %8.3f", static_cast<int>(width), r.node,
                                          r.visits, r.completions, r.success_rate));
    for (const std::string& o : outcomes) {
      const auto it = r.endings.find(o);
      absl::StrAppend(&out, absl::StrFormat(" %*d", std::max<int>(8, o.size()),
                                            it == r.endings.end() ? 0 : it->second));
    }
    out += "\n";
  }
  return out;
}

absl::StatusOr<ForceSweepReport> RunForceSweep(
    const LoadedConfig& config, const ControllerFactory& controllers,
    const ForceSweepOptions& o, const std::function<void(const std::string&)>& progress) {
  if (o.magnitudes.empty()) return absl::InvalidArgumentError("the force sweep needs magnitudes");
  for (size_t i = 1; i < o.magnitudes.size(); ++i) {
    if (!(o.magnitudes[i] > o.magnitudes[i - 1])) {
      return absl::InvalidArgumentError("force sweep magnitudes must be ascending");
    }
  }
  absl::StatusOr<const EnvFamily*> family = FamilyOf(config.run);
  if (!family.ok()) return family.status();
  auto say = [&](const std::string& line) {
    if (progress) progress(line);
  };
  // Evaluates `config` with `force` on the ball.
  auto evaluate = [&](const double force[3]) -> absl::StatusOr<EvalSummary> {
    LoadedConfig c = config;
    if (absl::Status s = (*family)->SetConstantBallForce(force, &c.run); !s.ok()) return s;
    absl::StatusOr<std::shared_ptr<const EnvSpec>> spec = CreateEnvSpec(c);
    if (!spec.ok()) return spec.status();
    absl::StatusOr<std::unique_ptr<Controller>> controller = controllers(*spec, c);
    if (!controller.ok()) return controller.status();
    absl::StatusOr<EpisodeReport> report = RunEpisodes(*spec, controller->get(), o.episodes);
    if (!report.ok()) return report.status();
    return Summarize(report->episodes, (*spec)->control_dt(), (*spec)->outcome_names());
  };
  ForceSweepReport report;
  std::optional<EvalSummary> baseline = o.baseline;
  const char axes[3] = {'x', 'y', 'z'};
  for (int axis = 0; axis < 3; ++axis) {
    for (const double sign : {1.0, -1.0}) {
      const std::string direction = absl::StrCat(sign > 0 ? "+" : "-", std::string(1, axes[axis]));
      double unit[3] = {0, 0, 0};
      unit[axis] = sign;
      LoadedConfig probe = config;
      if (absl::Status s = (*family)->SetConstantBallForce(unit, &probe.run); !s.ok()) {
        if (s.code() != absl::StatusCode::kUnimplemented) return s;
        report.unsupported[direction] = std::string(s.message());
        say(absl::StrCat(direction, ": not supported (", s.message(), ")"));
        continue;
      }
      double max_force = -1;
      bool passing = true;
      for (const double magnitude : o.magnitudes) {
        double force[3] = {0, 0, 0};
        force[axis] = sign * magnitude;
        EvalSummary summary;
        if (magnitude == 0 && baseline) {
          summary = *baseline;
        } else {
          absl::StatusOr<EvalSummary> s = evaluate(force);
          if (!s.ok()) return s.status();
          summary = *s;
          if (magnitude == 0) baseline = summary;
        }
        report.rows.push_back({direction, magnitude, summary});
        passing = passing && summary.median_juggles >= o.min_median_juggles;
        if (passing) max_force = magnitude;
        say(absl::StrFormat("%s %6.2f N: median_juggles=%g mean_juggles=%.2f", direction,
                            magnitude, summary.median_juggles, summary.mean_juggles));
      }
      report.max_force_n[direction] = max_force;
      report.directions.push_back(direction);
    }
  }
  return report;
}

std::string SummaryJson(const EvalSummary& s) {
  Json j = {{"table", "summary"}};
  j.update(SummaryToJson(s));
  return Line(j);
}

std::string NodeRowJson(const NodeRow& r) {
  return Line({{"table", "node"},
               {"node", r.node},
               {"visits", r.visits},
               {"completions", r.completions},
               {"success_rate", r.success_rate},
               {"endings", r.endings}});
}

std::string EdgeRowJson(const EdgeRow& r) {
  return Line({{"table", "edge"},
               {"from", r.from},
               {"to", r.to},
               {"chosen", r.chosen},
               {"completed", r.completed},
               {"failed", r.failed}});
}

std::string EpisodeJson(int episode, const EpisodeResult& e, double control_dt,
                        const std::vector<std::string>& outcome_names) {
  Json j = {{"table", "episode"},
            {"episode", episode},
            {"juggles", e.juggles},
            {"seconds", e.steps * control_dt},
            {"return", e.return_sum},
            {"outcome", OutcomeName(outcome_names, e.outcome)}};
  if (!e.ending_detail.empty()) j["ending_detail"] = e.ending_detail;
  for (const NamedValue& m : e.metrics) j[m.name] = m.value;  // the family's, per attempt
  return Line(j);
}

std::string ForceRowJson(const ForceSweepRow& r) {
  Json j = {{"table", "force_sweep"}, {"direction", r.direction}, {"force_n", r.force_n}};
  j.update(SummaryToJson(r.summary));
  return Line(j);
}

std::string ForceLimitJson(const std::string& direction, double max_force_n,
                           double min_median_juggles) {
  return Line({{"table", "force_limit"},
               {"direction", direction},
               {"max_force_n", max_force_n},
               {"min_median_juggles", min_median_juggles}});
}

}  // namespace juggle

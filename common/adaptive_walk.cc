#include "common/adaptive_walk.h"

#include <algorithm>
#include <utility>

#include "absl/strings/str_cat.h"

namespace juggle {

AdaptiveWalk::AdaptiveWalk(const ControlGraph* graph) : graph_(graph) {
  counts_.reserve(graph->num_edges());
  for (int e = 0; e < graph->num_edges(); ++e) counts_.push_back(graph->edge(e).base_weight);
}

int AdaptiveWalk::SampleEdge(int node, Rng* rng) const {
  const std::vector<int>& out = graph_->node(node).out_edges;
  if (!steering_.empty() && steering_[node] >= 0) {
    (void)rng->Uniform();  // the stream advances as it would unsteered
    return steering_[node];
  }
  double total = 0;
  for (int e : out) total += counts_[e];
  double u = rng->Uniform() * total;
  for (int e : out) {
    u -= counts_[e];
    if (u < 0) return e;
  }
  return out.back();  // rounding guard
}

absl::Status AdaptiveWalk::SetSteering(std::vector<int> edge_for_node) {
  if (edge_for_node.empty()) {
    steering_.clear();
    return absl::OkStatus();
  }
  if (static_cast<int>(edge_for_node.size()) != graph_->num_nodes()) {
    return absl::InvalidArgumentError(absl::StrCat("steering names ", edge_for_node.size(),
                                                   " nodes; the graph has ",
                                                   graph_->num_nodes()));
  }
  for (int n = 0; n < graph_->num_nodes(); ++n) {
    const int e = edge_for_node[n];
    if (e >= 0 && (e >= graph_->num_edges() || graph_->edge(e).from != n)) {
      return absl::InvalidArgumentError(
          absl::StrCat("steering: edge ", e, " does not leave node ", graph_->node(n).name));
    }
  }
  steering_ = std::move(edge_for_node);
  return absl::OkStatus();
}

absl::Status AdaptiveWalk::Apply(const EdgeEvent& event) {
  if (event.edge < 0 || event.edge >= graph_->num_edges()) {
    return absl::InvalidArgumentError(
        absl::StrCat("edge event for unknown edge ", event.edge, " (graph has ",
                     graph_->num_edges(), " edges)"));
  }
  const double w0 = graph_->edge(event.edge).base_weight;
  double& c = counts_[event.edge];
  switch (event.type) {
    case EdgeEventType::kChosen:
      c += w0;
      break;
    case EdgeEventType::kCompleted:
      c -= kCompletedDecrement * w0;
      break;
    case EdgeEventType::kFailed:
      break;
  }
  c = std::clamp(c, w0, kMaxCountFactor * w0);
  return absl::OkStatus();
}

absl::Status AdaptiveWalk::SetCounts(const std::vector<double>& counts) {
  if (static_cast<int>(counts.size()) != graph_->num_edges()) {
    return absl::InvalidArgumentError(absl::StrCat("edge counts have ", counts.size(),
                                                   " entries, the graph has ",
                                                   graph_->num_edges(), " edges"));
  }
  for (int e = 0; e < graph_->num_edges(); ++e) {
    const double w0 = graph_->edge(e).base_weight;
    if (!(counts[e] >= w0 && counts[e] <= kMaxCountFactor * w0)) {
      return absl::InvalidArgumentError(absl::StrCat("edge count ", counts[e], " of edge ", e,
                                                     " lies outside [", w0, ", ",
                                                     kMaxCountFactor * w0, "]"));
    }
  }
  counts_ = counts;
  return absl::OkStatus();
}

double AdaptiveWalk::Probability(int edge) const {
  double total = 0;
  for (int e : graph_->node(graph_->edge(edge).from).out_edges) total += counts_[e];
  return counts_[edge] / total;
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

}  // namespace juggle

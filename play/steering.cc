#include "play/steering.h"

#include <deque>
#include <optional>

#include "absl/strings/str_cat.h"

namespace juggle::play {

std::vector<int> SteerableNodes(const ControlGraph& graph) {
  std::vector<bool> entered(graph.num_nodes(), false);
  for (int e = 0; e < graph.num_edges(); ++e) entered[graph.edge(e).to] = true;
  std::vector<int> out;
  for (int n = 0; n < graph.num_nodes(); ++n) {
    if (entered[n]) out.push_back(n);
  }
  return out;
}

absl::StatusOr<std::vector<int>> SteerToward(const ControlGraph& graph, const std::string& target,
                                             int current) {
  const std::optional<int> t = graph.FindNode(target);
  if (!t.has_value()) {
    return absl::InvalidArgumentError(absl::StrCat("the graph has no node \"", target, "\""));
  }
  // Breadth-first from the target over reversed edges: dist[n] = edges from n to the target
  // (the target's own distance is that of its shortest cycle back to itself).
  const int n_nodes = graph.num_nodes();
  std::vector<int> dist(n_nodes, -1), edge(n_nodes, -1);
  std::deque<int> frontier;
  for (int e = 0; e < graph.num_edges(); ++e) {
    if (graph.edge(e).to == *t && edge[graph.edge(e).from] < 0) {
      edge[graph.edge(e).from] = e;
      dist[graph.edge(e).from] = 1;
      frontier.push_back(graph.edge(e).from);
    }
  }
  if (frontier.empty()) {
    return absl::InvalidArgumentError(
        absl::StrCat("no edge of the graph leads into \"", target, "\": it is a start only"));
  }
  while (!frontier.empty()) {
    const int n = frontier.front();
    frontier.pop_front();
    for (int e = 0; e < graph.num_edges(); ++e) {
      const int from = graph.edge(e).from;
      if (graph.edge(e).to == n && dist[from] < 0) {
        dist[from] = dist[n] + 1;
        edge[from] = e;
        frontier.push_back(from);
      }
    }
  }
  if (current >= 0 && current < n_nodes && current != *t && dist[current] < 0) {
    return absl::InvalidArgumentError(absl::StrCat("\"", target, "\" cannot be reached from \"",
                                                   graph.node(current).name, "\""));
  }
  return edge;
}

}  // namespace juggle::play

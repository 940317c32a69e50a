// The control graph (paper §4): immutable nodes and weighted directed edges, validated once.
// Shared read-only by every env; thread-safe to read.
#ifndef JUGGLE_COMMON_CONTROL_GRAPH_H_
#define JUGGLE_COMMON_CONTROL_GRAPH_H_

#include <optional>
#include <string>
#include <vector>

#include "absl/status/statusor.h"
#include "common/source_locator.h"
#include "proto/run_config.pb.h"

namespace juggle {

struct GraphEdge {
  int from = -1;
  int to = -1;
  double base_weight = 1.0;  // w0 of the adaptive walk
};

struct GraphNode {
  std::string name;
  config::Stage stage = config::STAGE_UNSPECIFIED;
  config::NodeSpec spec;        // the node as configured
  std::vector<int> out_edges;   // indices into ControlGraph::edges(), in config order
  bool initial = false;
};

class ControlGraph {
 public:
  // Validates `proto` and builds the graph. INVALID_ARGUMENT, with `where` naming the file,
  // line and field, for: no nodes; empty, duplicate or stage-less nodes; missing contact
  // bodies or pose; heights at or below the contact height; edges to or from missing nodes;
  // non-positive or duplicate edges; nodes without outgoing edges; stage-inconsistent edges
  // (DOWN -> UP|STALL, UP -> DOWN, STALL -> STALL|UP); no initial node or a non-DOWN one; nodes
  // unreachable from the initial nodes.
  static absl::StatusOr<ControlGraph> Build(const config::ControlGraph& proto,
                                            const SourceLocator& where);

  int num_nodes() const { return static_cast<int>(nodes_.size()); }
  int num_edges() const { return static_cast<int>(edges_.size()); }
  const GraphNode& node(int i) const { return nodes_[i]; }
  const GraphEdge& edge(int i) const { return edges_[i]; }
  const std::vector<int>& initial_nodes() const { return initial_nodes_; }
  std::optional<int> FindNode(const std::string& name) const;
  // The edge from -> to, if any.
  std::optional<int> FindEdge(int from, int to) const;

 private:
  std::vector<GraphNode> nodes_;
  std::vector<GraphEdge> edges_;
  std::vector<int> initial_nodes_;
};

// Apex height of node `n`'s flight when it has a fixed height (apex_height, or derived from
// half_cycle_s); for ranged nodes, the range's minimum.
double NominalApexHeight(const config::NodeSpec& n, double gravity);

}  // namespace juggle

#endif  // JUGGLE_COMMON_CONTROL_GRAPH_H_

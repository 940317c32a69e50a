#include "common/control_graph.h"

#include <deque>
#include <set>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_join.h"

namespace juggle {
namespace {

absl::Status Invalid(const SourceLocator& where, const FieldPath& path, const std::string& what) {
  return absl::InvalidArgumentError(absl::StrCat(where.Where(path), ": ", what));
}

bool EdgeAllowed(config::Stage from, config::Stage to) {
  switch (from) {
    case config::DOWN:
      return to == config::UP || to == config::STALL;
    case config::UP:
      return to == config::DOWN;
    case config::STALL:
      return to == config::STALL || to == config::UP;
    default:
      return false;
  }
}

absl::Status ValidateNode(const config::NodeSpec& n, int i, const SourceLocator& where) {
  const FieldStep self{"node", i};
  if (n.name().empty()) return Invalid(where, {self, {"name"}}, "node needs a name");
  if (n.stage() == config::STAGE_UNSPECIFIED) {
    return Invalid(where, {self, {"stage"}},
                   absl::StrCat("node '", n.name(), "' needs a stage (DOWN, UP or STALL)"));
  }
  if (n.contact_body_size() == 0) {
    return Invalid(where, {self, {"contact_body"}},
                   absl::StrCat("node '", n.name(), "' lists no contact_body"));
  }
  if (n.pose().generator_case() == config::ReferencePose::GENERATOR_NOT_SET) {
    return Invalid(where, {self, {"pose"}},
                   absl::StrCat("node '", n.name(), "' needs a reference pose generator"));
  }
  if (!n.has_contact_height() || n.contact_height() <= 0) {
    return Invalid(where, {self, {"contact_height"}},
                   absl::StrCat("node '", n.name(), "' needs contact_height > 0"));
  }
  if (n.contact_window_s() < 0) {
    return Invalid(where, {self, {"contact_window_s"}}, "must be >= 0");
  }
  if (n.initial() && n.stage() != config::DOWN) {
    return Invalid(where, {self, {"initial"}},
                   absl::StrCat("node '", n.name(), "' is not a DOWN node and cannot start an "
                                "episode (the ball starts at its apex)"));
  }
  if (n.stage() == config::STALL) {
    if (!n.has_stall() || n.stall().body().empty()) {
      return Invalid(where, {self, {"stall"}},
                     absl::StrCat("STALL node '", n.name(), "' needs stall { body: ... }"));
    }
    return absl::OkStatus();
  }
  if (n.has_half_cycle_s()) {
    if (n.half_cycle_s() <= 0) return Invalid(where, {self, {"half_cycle_s"}}, "must be > 0");
  } else if (n.has_apex_height_range()) {
    const auto& r = n.apex_height_range();
    if (r.min() <= n.contact_height()) {
      return Invalid(where, {self, {"apex_height_range"}, {"min"}},
                     absl::StrCat("apex height ", r.min(), " must exceed contact_height ",
                                  n.contact_height()));
    }
    if (r.max() < r.min()) {
      return Invalid(where, {self, {"apex_height_range"}, {"max"}}, "max must be >= min");
    }
  } else if (!n.has_apex_height() || n.apex_height() <= n.contact_height()) {
    return Invalid(where, {self, {"apex_height"}},
                   absl::StrCat("node '", n.name(), "': apex_height ", n.apex_height(),
                                " must exceed contact_height ", n.contact_height()));
  }
  if (n.has_around_the_world()) {
    const auto& atw = n.around_the_world();
    if (atw.foot_body().empty()) {
      return Invalid(where, {self, {"around_the_world"}, {"foot_body"}}, "needs a foot_body");
    }
    if (atw.max_angle_deg() <= 0 || atw.max_angle_deg() > 180) {
      return Invalid(where, {self, {"around_the_world"}, {"max_angle_deg"}},
                     "must be in (0, 180]");
    }
  }
  return absl::OkStatus();
}

}  // namespace

double NominalApexHeight(const config::NodeSpec& n, double gravity) {
  if (n.has_half_cycle_s()) {
    return n.contact_height() + 0.5 * gravity * n.half_cycle_s() * n.half_cycle_s();
  }
  if (n.has_apex_height_range()) return n.apex_height_range().min();
  return n.apex_height();
}

absl::StatusOr<ControlGraph> ControlGraph::Build(const config::ControlGraph& proto,
                                                 const SourceLocator& where) {
  ControlGraph g;
  if (proto.node_size() == 0) return Invalid(where, {{"node"}}, "the graph has no nodes");
  for (int i = 0; i < proto.node_size(); ++i) {
    const config::NodeSpec& n = proto.node(i);
    if (absl::Status s = ValidateNode(n, i, where); !s.ok()) return s;
    if (g.FindNode(n.name()).has_value()) {
      return Invalid(where, {{"node", i}, {"name"}},
                     absl::StrCat("duplicate node name '", n.name(), "'"));
    }
    GraphNode node;
    node.name = n.name();
    node.stage = n.stage();
    node.spec = n;
    node.initial = n.initial();
    if (node.initial) g.initial_nodes_.push_back(i);
    g.nodes_.push_back(std::move(node));
  }
  std::vector<std::string> names;
  for (const GraphNode& n : g.nodes_) names.push_back(n.name);

  for (int e = 0; e < proto.edge_size(); ++e) {
    const config::EdgeSpec& spec = proto.edge(e);
    const std::optional<int> from = g.FindNode(spec.from());
    const std::optional<int> to = g.FindNode(spec.to());
    if (!from) {
      return Invalid(where, {{"edge", e}, {"from"}},
                     absl::StrCat("unknown node '", spec.from(), "' (nodes: ",
                                  absl::StrJoin(names, ", "), ")"));
    }
    if (!to) {
      return Invalid(where, {{"edge", e}, {"to"}},
                     absl::StrCat("unknown node '", spec.to(), "' (nodes: ",
                                  absl::StrJoin(names, ", "), ")"));
    }
    if (!(spec.weight() > 0)) {
      return Invalid(where, {{"edge", e}, {"weight"}},
                     absl::StrCat("edge weight must be > 0, got ", spec.weight()));
    }
    if (g.FindEdge(*from, *to).has_value()) {
      return Invalid(where, {{"edge", e}},
                     absl::StrCat("duplicate edge ", spec.from(), " -> ", spec.to()));
    }
    if (!EdgeAllowed(g.nodes_[*from].stage, g.nodes_[*to].stage)) {
      return Invalid(where, {{"edge", e}},
                     absl::StrCat("edge ", spec.from(), " -> ", spec.to(), " joins ",
                                  config::Stage_Name(g.nodes_[*from].stage), " to ",
                                  config::Stage_Name(g.nodes_[*to].stage),
                                  "; allowed: DOWN->UP|STALL, UP->DOWN, STALL->STALL|UP"));
    }
    g.nodes_[*from].out_edges.push_back(g.num_edges());
    g.edges_.push_back(GraphEdge{*from, *to, spec.weight()});
  }
  for (int i = 0; i < g.num_nodes(); ++i) {
    if (g.nodes_[i].out_edges.empty()) {
      return Invalid(where, {{"node", i}, {"name"}},
                     absl::StrCat("node '", g.nodes_[i].name, "' has no outgoing edge"));
    }
  }
  if (g.initial_nodes_.empty()) {
    return Invalid(where, {{"node"}}, "no node is marked 'initial: true'");
  }
  // Every node must be reachable from an initial node: an unreachable skill is never trained.
  std::vector<bool> seen(g.num_nodes(), false);
  std::deque<int> queue(g.initial_nodes_.begin(), g.initial_nodes_.end());
  for (int i : g.initial_nodes_) seen[i] = true;
  while (!queue.empty()) {
    const int n = queue.front();
    queue.pop_front();
    for (int e : g.nodes_[n].out_edges) {
      if (!seen[g.edges_[e].to]) {
        seen[g.edges_[e].to] = true;
        queue.push_back(g.edges_[e].to);
      }
    }
  }
  for (int i = 0; i < g.num_nodes(); ++i) {
    if (!seen[i]) {
      return Invalid(where, {{"node", i}, {"name"}},
                     absl::StrCat("node '", g.nodes_[i].name,
                                  "' is unreachable from every initial node"));
    }
  }
  return g;
}

std::optional<int> ControlGraph::FindNode(const std::string& name) const {
  for (int i = 0; i < num_nodes(); ++i) {
    if (nodes_[i].name == name) return i;
  }
  return std::nullopt;
}

std::optional<int> ControlGraph::FindEdge(int from, int to) const {
  for (int e : nodes_[from].out_edges) {
    if (edges_[e].to == to) return e;
  }
  return std::nullopt;
}

}  // namespace juggle

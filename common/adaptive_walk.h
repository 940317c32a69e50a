// Adaptive random walk over the control graph (paper §5.2). One count per edge, starting at
// the edge's base weight w0. Successors are sampled with probability ∝ count. Events:
//   kChosen    (+w0)   the edge was traversed (the walk entered its target node),
//   kCompleted (−2·w0) the target node was completed (no termination while in it),
//   kFailed    (none)  the episode ended while in the target node: the +w0 stays.
// Counts are clamped to [w0, 100·w0] after every event. The learner owns the counts in a
// distributed run: workers sample from a snapshot (SetCounts) and report their events.
// Thread-compatible: concurrent SampleEdge calls are safe while no one calls Apply/SetCounts.
#ifndef JUGGLE_COMMON_ADAPTIVE_WALK_H_
#define JUGGLE_COMMON_ADAPTIVE_WALK_H_

#include <cstdint>
#include <vector>

#include "absl/status/status.h"
#include "common/control_graph.h"
#include "common/rng.h"

namespace juggle {

enum class EdgeEventType : uint8_t { kChosen = 0, kCompleted = 1, kFailed = 2 };

struct EdgeEvent {
  int32_t edge = -1;
  EdgeEventType type = EdgeEventType::kChosen;
  bool operator==(const EdgeEvent& o) const { return edge == o.edge && type == o.type; }
};

// Workers' edge events per edge (paper §5.2: chosen = the walk entered the edge's target,
// completed = the target node was completed, failed = the episode ended in it).
struct WalkEventTotals {
  std::vector<int64_t> chosen, completed, failed;  // [num_edges]
  void Resize(int num_edges);
  void Add(const EdgeEvent& event);                // events of unknown edges are ignored
  void Add(const WalkEventTotals& other);
  int64_t events() const;
};

class AdaptiveWalk {
 public:
  static constexpr double kMaxCountFactor = 100.0;
  static constexpr double kCompletedDecrement = 2.0;

  // REQUIRES: `graph` outlives this object.
  explicit AdaptiveWalk(const ControlGraph* graph);

  // Samples an outgoing edge of `node` ∝ counts; returns the edge index. A steered node
  // (SetSteering) returns its steered edge instead (drawing from `rng` all the same).
  int SampleEdge(int node, Rng* rng) const;

  // The live page's skill choice (play/steering.h): per node, the edge to take from it, or −1
  // to sample as usual; empty: no steering. INVALID_ARGUMENT (nothing changed) for a size
  // other than the number of nodes or an edge that does not leave its node.
  absl::Status SetSteering(std::vector<int> edge_for_node);
  const std::vector<int>& steering() const { return steering_; }

  // Applies one event with the counting rule above. INVALID_ARGUMENT for an unknown edge.
  absl::Status Apply(const EdgeEvent& event);

  // Replaces all counts (e.g. from a learner snapshot). INVALID_ARGUMENT if the size differs
  // from the number of edges or a count lies outside [w0, 100·w0].
  absl::Status SetCounts(const std::vector<double>& counts);

  const std::vector<double>& counts() const { return counts_; }
  double count(int edge) const { return counts_[edge]; }
  // Probability of taking `edge` from its source node under the current counts.
  double Probability(int edge) const;

 private:
  const ControlGraph* graph_;
  std::vector<double> counts_;
  std::vector<int> steering_;  // empty, or an edge (or −1) per node
};

}  // namespace juggle

#endif  // JUGGLE_COMMON_ADAPTIVE_WALK_H_

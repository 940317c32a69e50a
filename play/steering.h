// The skill choice of the live page as a steering of the adaptive walk
// (AdaptiveWalk::SetSteering): from every node that can reach the chosen one, the first edge of
// a shortest path to it; from the chosen node on, the walk comes back to it whenever an edge
// allows (its skill repeats). Pure; thread-safe.
#ifndef JUGGLE_PLAY_STEERING_H_
#define JUGGLE_PLAY_STEERING_H_

#include <string>
#include <vector>

#include "absl/status/statusor.h"
#include "common/control_graph.h"

namespace juggle::play {

// Per node, the edge toward `target` (−1: none needed or none possible). INVALID_ARGUMENT, with
// a message for the page, when the graph has no node `target`, no edge leads into it, or it
// cannot be reached from `current`.
absl::StatusOr<std::vector<int>> SteerToward(const ControlGraph& graph, const std::string& target,
                                             int current);

// The nodes a skill choice may name: every node with an edge into it, in node order.
std::vector<int> SteerableNodes(const ControlGraph& graph);

}  // namespace juggle::play

#endif  // JUGGLE_PLAY_STEERING_H_

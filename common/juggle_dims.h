// Sizes of the juggling task's interface, shared by workers and the learner.
#ifndef JUGGLE_COMMON_JUGGLE_DIMS_H_
#define JUGGLE_COMMON_JUGGLE_DIMS_H_

namespace juggle {

constexpr int kNumActions = 28;    // actuated DoF of the humanoid
constexpr int kObsBase = 88;       // observation size before the three node one-hots

// Observation size for a control graph with `num_nodes` nodes.
constexpr int ObservationSize(int num_nodes) { return kObsBase + 3 * num_nodes; }

}  // namespace juggle

#endif  // JUGGLE_COMMON_JUGGLE_DIMS_H_

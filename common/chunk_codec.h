// UnrollBatch <-> rpc::TrajectoryChunk: a worker's contribution (one unroll per env) split into
// chunks below a byte budget, and the learner-side decoding with validation of everything the
// wire can get wrong. Stateless functions.
#ifndef JUGGLE_COMMON_CHUNK_CODEC_H_
#define JUGGLE_COMMON_CHUNK_CODEC_H_

#include <cstdint>
#include <vector>

#include "absl/status/statusor.h"
#include "common/adaptive_walk.h"
#include "common/episode_counters.h"
#include "common/expert_counters.h"
#include "common/unroll_batch.h"
#include "proto/rollout.pb.h"

namespace juggle {

struct Contribution {
  UnrollBatch batch;              // its unrolls (policy_version set per unroll)
  std::vector<int32_t> node;      // [U, T]
  std::vector<EdgeEvent> events;
  EpisodeCounters stats;
  // Episodes the expert drove (episodes, length_sum and juggles_sum are carried).
  EpisodeCounters expert_stats;
  // What the expert's labels cost (planner-guided training; zero without labels).
  ExpertCounters expert_cost;
};

// Splits `c` into chunks of at most ~max_bytes payload each (at least one unroll per chunk).
std::vector<rpc::TrajectoryChunk> EncodeContribution(const Contribution& c, uint64_t incarnation,
                                                     int64_t sequence, size_t max_bytes);

// Decodes one chunk. INVALID_ARGUMENT (naming the field) for inconsistent sizes, flags other
// than 0/1, non-finite values, node ids outside [0, num_nodes), edge events outside
// [0, num_edges) or of unknown type, obs/act dims other than expected, labels that disagree with
// their masks or are not finite.
absl::StatusOr<Contribution> DecodeChunk(const rpc::TrajectoryChunk& chunk, int obs_dim,
                                         int act_dim, int num_nodes, int num_edges);

// Appends `part`'s unrolls, nodes, events and stats to `into` (dims must match).
void AppendContribution(Contribution* into, const Contribution& part);

}  // namespace juggle

#endif  // JUGGLE_COMMON_CHUNK_CODEC_H_

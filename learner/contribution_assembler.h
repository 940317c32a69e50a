// Turns chunk parts into complete contributions and complete contributions into training
// batches, by the learner's mode:
//   synchronous: a batch for version v is ready when every live worker slot has a complete
//     contribution of version v; it holds those contributions in slot order (deterministic).
//   asynchronous: a batch is ready when complete contributions no older than the lag add up
//     to the wanted number of unrolls; older ones are dropped and counted.
// Partial contributions of a dead incarnation are discarded; complete ones are kept (the
// learner accepted them). Thread-compatible: used by the learner's training thread only.
#ifndef JUGGLE_LEARNER_CONTRIBUTION_ASSEMBLER_H_
#define JUGGLE_LEARNER_CONTRIBUTION_ASSEMBLER_H_

#include <cstdint>
#include <map>
#include <optional>
#include <tuple>
#include <vector>

#include "absl/status/status.h"
#include "common/chunk_codec.h"

namespace juggle {

struct ChunkPart {
  int slot = -1;
  uint64_t incarnation = 0;
  int64_t sequence = 0;
  int part = 0;
  int num_parts = 1;
  int64_t version = 0;
  Contribution data;
};

class ContributionAssembler {
 public:
  // Adds a part; when it completes its contribution, the contribution becomes available.
  // INVALID_ARGUMENT (nothing kept) if the part disagrees with the parts already held for its
  // contribution (num_parts, unroll length, dims). Parts of a contribution that already
  // completed, and duplicate parts, are ignored.
  absl::Status Add(ChunkPart part);
  // Discards the partial contributions of `incarnation`; returns how many parts were dropped.
  int DropIncarnation(uint64_t incarnation);
  // Discards the partial contributions of every incarnation not in `live`.
  int DropAllBut(const std::vector<uint64_t>& live);

  // Synchronous: the batch of `version` if every slot in `live_slots` (at least one) has a
  // complete contribution of it. Contributions of older versions are discarded (counted in
  // *dropped_unrolls).
  std::optional<Contribution> TakeSync(int64_t version, const std::vector<int>& live_slots,
                                       int64_t* dropped_unrolls);
  // Asynchronous: a batch of at least `unrolls` unrolls with versions in
  // [version − max_lag, version], oldest first.
  std::optional<Contribution> TakeAsync(int64_t version, int64_t max_lag, int unrolls,
                                        int64_t* dropped_unrolls);

  int pending_parts() const;
  // The slots of `slots` without a complete contribution of `version` (what a synchronous
  // iteration still waits for).
  std::vector<int> MissingSlots(int64_t version, const std::vector<int>& slots) const;

 private:
  struct Complete {
    int slot;
    int64_t version;
    Contribution data;
  };
  // (incarnation, version, sequence) -> parts received so far.
  std::map<std::tuple<uint64_t, int64_t, int64_t>, std::vector<ChunkPart>> partial_;
  // Highest completed sequence per incarnation: later copies of its parts are ignored.
  std::map<uint64_t, int64_t> completed_;
  std::vector<Complete> complete_;  // arrival order
};

}  // namespace juggle

#endif  // JUGGLE_LEARNER_CONTRIBUTION_ASSEMBLER_H_

// Turns chunk parts into complete contributions and complete contributions into training
// batches, by the learner's mode:
//   synchronous: a batch for version v is ready when every live worker slot has a complete
//     contribution of version v; it holds those contributions in slot order (deterministic).
//   asynchronous: a batch is ready when complete contributions no older than the lag add up
//     to the wanted number of unrolls; older ones are dropped and counted.
// Partial contributions of a dead incarnation are discarded; complete ones are kept (the
// learner accepted them).
// Memory is bounded whatever a worker sends: a contribution holds at most its worker's env
// count of unrolls, an incarnation has at most kMaxPartialPerIncarnation contributions in
// assembly (a new one evicts its oldest), and a slot at most versions_kept + ⌈wanted_unrolls /
// its env count⌉ complete ones waiting (a new one evicts its oldest): enough for the batches
// of the versions a batch may use. Evicted unrolls are counted in evicted_unrolls().
// Thread-compatible: used by the learner's training thread only.
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
  int max_unrolls = 1 << 30;  // the worker's env count: unrolls of one whole contribution
  Contribution data;
};

class ContributionAssembler {
 public:
  static constexpr int kMaxPartialPerIncarnation = 2;
  // versions_kept: versions a batch may mix (synchronous 1, asynchronous max_policy_lag + 1)
  // plus slack; wanted_unrolls: an asynchronous batch's size (0: one contribution per slot).
  explicit ContributionAssembler(int versions_kept = 4, int wanted_unrolls = 0)
      : versions_kept_(versions_kept), wanted_unrolls_(wanted_unrolls) {}

  // Adds a part; when it completes its contribution, the contribution becomes available.
  // INVALID_ARGUMENT (nothing kept) if the part disagrees with the parts already held for its
  // contribution (num_parts, unroll length, dims) or the parts add up to more unrolls than
  // max_unrolls (the contribution is then dropped). Parts of a contribution that already
  // completed, and duplicate parts, are ignored.
  absl::Status Add(ChunkPart part);
  // Discards the partial contributions of `incarnation`; returns how many parts were dropped.
  int DropIncarnation(uint64_t incarnation);
  // Discards the partial contributions of every incarnation not in `live`.
  int DropAllBut(const std::vector<uint64_t>& live);
  // Discards partial contributions of versions below `min_version` (they could never be
  // trained on, e.g. a worker's later part was refused as stale); returns their unrolls.
  int64_t DropPartialsOlderThan(int64_t min_version);

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
  int64_t evicted_unrolls() const { return evicted_unrolls_; }
  // Unrolls of duplicate parts and of parts of already completed contributions (ignored).
  int64_t ignored_unrolls() const { return ignored_unrolls_; }
  // Unrolls in contributions still being assembled.
  int64_t partial_unrolls() const;
  // Unrolls held in complete contributions not yet taken.
  int64_t held_unrolls() const;
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
  const int versions_kept_;
  const int wanted_unrolls_;
  int64_t evicted_unrolls_ = 0;
  int64_t ignored_unrolls_ = 0;
};

}  // namespace juggle

#endif  // JUGGLE_LEARNER_CONTRIBUTION_ASSEMBLER_H_

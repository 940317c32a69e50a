#include "learner/contribution_assembler.h"

#include <algorithm>
#include <climits>
#include <set>

#include "absl/strings/str_cat.h"

namespace juggle {

absl::Status ContributionAssembler::Add(ChunkPart part) {
  auto done = completed_.find(part.incarnation);
  if (done != completed_.end() && part.sequence <= done->second) {
    ignored_unrolls_ += part.data.batch.num_unrolls;
    return absl::OkStatus();
  }
  const auto key = std::make_tuple(part.incarnation, part.version, part.sequence);
  auto found = partial_.find(key);
  if (found == partial_.end()) {
    // A new contribution in assembly: evict this incarnation's oldest beyond the bound.
    std::vector<decltype(partial_)::iterator> mine;
    for (auto it = partial_.lower_bound({part.incarnation, INT64_MIN, INT64_MIN});
         it != partial_.end() && std::get<0>(it->first) == part.incarnation; ++it) {
      mine.push_back(it);
    }
    for (size_t i = 0; i + kMaxPartialPerIncarnation <= mine.size(); ++i) {
      for (const ChunkPart& p : mine[i]->second) evicted_unrolls_ += p.data.batch.num_unrolls;
      partial_.erase(mine[i]);
    }
    found = partial_.emplace(key, std::vector<ChunkPart>()).first;
  }
  std::vector<ChunkPart>& parts = found->second;
  int64_t unrolls = part.data.batch.num_unrolls;
  for (const ChunkPart& p : parts) {
    if (p.part == part.part) {  // duplicate part: ignore
      ignored_unrolls_ += part.data.batch.num_unrolls;
      return absl::OkStatus();
    }
    const UnrollBatch& a = p.data.batch;
    const UnrollBatch& b = part.data.batch;
    if (p.num_parts != part.num_parts || a.unroll_length != b.unroll_length ||
        a.obs_dim != b.obs_dim || a.act_dim != b.act_dim) {
      return absl::InvalidArgumentError(absl::StrCat(
          "part ", part.part, " of contribution ", part.sequence,
          " disagrees with its other parts (num_parts, unroll length or dimensions)"));
    }
    unrolls += a.num_unrolls;
  }
  if (unrolls > part.max_unrolls) {
    for (const ChunkPart& p : parts) evicted_unrolls_ += p.data.batch.num_unrolls;
    partial_.erase(found);
    return absl::InvalidArgumentError(absl::StrCat(
        "the parts of contribution ", part.sequence, " carry ", unrolls,
        " unrolls; the worker has ", part.max_unrolls, " envs"));
  }
  const int num_parts = part.num_parts;
  parts.push_back(std::move(part));
  if (static_cast<int>(parts.size()) < num_parts) return absl::OkStatus();
  std::sort(parts.begin(), parts.end(), [](const ChunkPart& a, const ChunkPart& b) { return a.part < b.part; });
  Complete c{parts[0].slot, parts[0].version, Contribution()};
  for (const ChunkPart& p : parts) AppendContribution(&c.data, p.data);
  // The slot's oldest waiting contributions give way beyond the bound.
  const int64_t envs = std::max(1, parts[0].max_unrolls);
  const int64_t per_slot = versions_kept_ + (wanted_unrolls_ + envs - 1) / envs;
  int64_t of_slot = 0;
  for (const Complete& held : complete_) of_slot += held.slot == c.slot;
  for (auto it = complete_.begin(); it != complete_.end() && of_slot >= per_slot;) {
    if (it->slot == c.slot) {
      evicted_unrolls_ += it->data.batch.num_unrolls;
      it = complete_.erase(it);
      --of_slot;
    } else {
      ++it;
    }
  }
  complete_.push_back(std::move(c));
  partial_.erase(found);
  int64_t& last = completed_[std::get<0>(key)];
  last = std::max(last, std::get<2>(key));
  return absl::OkStatus();
}

int64_t ContributionAssembler::DropPartialsOlderThan(int64_t min_version) {
  int64_t dropped = 0;
  for (auto it = partial_.begin(); it != partial_.end();) {
    if (std::get<1>(it->first) < min_version) {
      for (const ChunkPart& p : it->second) dropped += p.data.batch.num_unrolls;
      it = partial_.erase(it);
    } else {
      ++it;
    }
  }
  return dropped;
}

int64_t ContributionAssembler::held_unrolls() const {
  int64_t n = 0;
  for (const Complete& c : complete_) n += c.data.batch.num_unrolls;
  return n;
}

int ContributionAssembler::DropIncarnation(uint64_t incarnation) {
  int dropped = 0;
  for (auto it = partial_.begin(); it != partial_.end();) {
    if (std::get<0>(it->first) == incarnation) {
      dropped += static_cast<int>(it->second.size());
      it = partial_.erase(it);
    } else {
      ++it;
    }
  }
  return dropped;
}

int ContributionAssembler::DropAllBut(const std::vector<uint64_t>& live) {
  const std::set<uint64_t> keep(live.begin(), live.end());
  for (auto it = completed_.begin(); it != completed_.end();) {
    it = keep.count(it->first) ? std::next(it) : completed_.erase(it);
  }
  int dropped = 0;
  for (auto it = partial_.begin(); it != partial_.end();) {
    if (!keep.count(std::get<0>(it->first))) {
      dropped += static_cast<int>(it->second.size());
      it = partial_.erase(it);
    } else {
      ++it;
    }
  }
  return dropped;
}

std::vector<int> ContributionAssembler::MissingSlots(int64_t version,
                                                     const std::vector<int>& slots) const {
  std::set<int> have;
  for (const Complete& c : complete_) {
    if (c.version == version) have.insert(c.slot);
  }
  std::vector<int> missing;
  for (int slot : slots) {
    if (!have.count(slot)) missing.push_back(slot);
  }
  return missing;
}

std::optional<Contribution> ContributionAssembler::TakeSync(int64_t version,
                                                            const std::vector<int>& live_slots,
                                                            int64_t* dropped_unrolls) {
  // Discard what can never be used.
  for (auto it = complete_.begin(); it != complete_.end();) {
    if (it->version < version) {
      *dropped_unrolls += it->data.batch.num_unrolls;
      it = complete_.erase(it);
    } else {
      ++it;
    }
  }
  if (live_slots.empty()) return std::nullopt;
  std::set<int> have;
  for (const Complete& c : complete_) {
    if (c.version == version) have.insert(c.slot);
  }
  for (int slot : live_slots) {
    if (!have.count(slot)) return std::nullopt;
  }
  // Every live slot is in: take all of this version's contributions (dead workers' complete
  // ones included), in slot order. One contribution per slot: the first that arrived.
  std::vector<Complete> chosen;
  std::set<int> taken;
  for (auto it = complete_.begin(); it != complete_.end();) {
    if (it->version == version && !taken.count(it->slot)) {
      taken.insert(it->slot);
      chosen.push_back(std::move(*it));
      it = complete_.erase(it);
    } else {
      ++it;
    }
  }
  std::sort(chosen.begin(), chosen.end(), [](const Complete& a, const Complete& b) { return a.slot < b.slot; });
  Contribution batch;
  for (const Complete& c : chosen) AppendContribution(&batch, c.data);
  return batch;
}

std::optional<Contribution> ContributionAssembler::TakeAsync(int64_t version, int64_t max_lag,
                                                             int unrolls,
                                                             int64_t* dropped_unrolls) {
  int available = 0;
  for (auto it = complete_.begin(); it != complete_.end();) {
    if (it->version < version - max_lag) {
      *dropped_unrolls += it->data.batch.num_unrolls;
      it = complete_.erase(it);
    } else {
      available += it->data.batch.num_unrolls;
      ++it;
    }
  }
  if (available < unrolls || complete_.empty()) return std::nullopt;
  Contribution batch;
  int taken = 0;
  while (!complete_.empty() && taken < unrolls) {
    taken += complete_.front().data.batch.num_unrolls;
    AppendContribution(&batch, complete_.front().data);
    complete_.erase(complete_.begin());
  }
  return batch;
}

int ContributionAssembler::pending_parts() const {
  int n = 0;
  for (const auto& [key, parts] : partial_) n += static_cast<int>(parts.size());
  return n;
}

int64_t ContributionAssembler::partial_unrolls() const {
  int64_t n = 0;
  for (const auto& [key, parts] : partial_) {
    for (const ChunkPart& p : parts) n += p.data.batch.num_unrolls;
  }
  return n;
}

}  // namespace juggle

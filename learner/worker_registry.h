// The learner's view of its workers: slots, incarnations and heartbeats. A registration gets
// a slot (its worker index: it seeds the worker's envs) and a fresh incarnation id; a new
// registration for an occupied slot replaces the old incarnation (a restarted worker).
// Registrations are bounded (RegistryLimits): the registry's memory, the learner's metric
// series per slot and the workers a synchronous round waits for cannot grow with what peers
// claim. Thread-safe.
#ifndef JUGGLE_LEARNER_WORKER_REGISTRY_H_
#define JUGGLE_LEARNER_WORKER_REGISTRY_H_

#include <chrono>
#include <cstdint>
#include <map>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "absl/status/statusor.h"

namespace juggle {

struct RegistryLimits {
  int max_workers = 256;           // live registrations in total; slots are [0, max_workers)
  int max_workers_per_host = 64;   // live registrations with the same host name
  int max_envs_per_worker = 1024;
  static constexpr size_t kMaxHostBytes = 253;  // a DNS name's limit
};

struct WorkerInfo {
  int slot = -1;
  uint64_t incarnation = 0;
  int num_envs = 0;
  std::string host;
  std::chrono::steady_clock::time_point last_seen;
  int64_t policy_version = -1;
  double env_steps_per_s = 0;
  int64_t chunks_accepted = 0;   // chunks of this incarnation enqueued for training
  int64_t chunks_rejected = 0;   // chunks of this incarnation refused (any reason)
  int64_t newest_chunk_version = -1;  // newest policy version of its chunks, accepted or not
  int64_t sessions = 1;  // the worker process's registrations so far, this one included
};

class WorkerRegistry {
 public:
  using Clock = std::chrono::steady_clock;
  // `epoch` makes incarnation ids unique across learner restarts (high 32 bits).
  explicit WorkerRegistry(uint32_t epoch, RegistryLimits limits = {})
      : limits_(limits), next_incarnation_(uint64_t(epoch) << 32 | 1) {}

  // requested_slot < 0: the lowest free slot. Returns the new record; `replaced` receives the
  // incarnation that held the slot before, if any (a replacement does not count against the
  // limits). INVALID_ARGUMENT for a slot outside [-1, max_workers), num_envs outside
  // [1, max_envs_per_worker] or a host name that is empty, too long or not printable ASCII;
  // RESOURCE_EXHAUSTED when max_workers or the host's max_workers_per_host are live.
  // `sessions_before`: the worker's own count of its earlier registrations (clamped to
  // [0, 2^40]; it is the peer's claim, shown, never trusted for anything else).
  absl::StatusOr<WorkerInfo> Register(int requested_slot, int num_envs, const std::string& host,
                                      Clock::time_point now, std::optional<uint64_t>* replaced,
                                      int64_t sessions_before = 0);
  const RegistryLimits& limits() const { return limits_; }
  // Records a sign of life. False if the incarnation is unknown.
  bool Touch(uint64_t incarnation, Clock::time_point now, int64_t policy_version = -1,
             double env_steps_per_s = -1);
  std::optional<WorkerInfo> Find(uint64_t incarnation) const;
  // Counts a chunk of `incarnation` as accepted or rejected (unknown incarnations: ignored).
  // `policy_version` (the caller passes only versions the learner has published; -1: none)
  // raises newest_chunk_version.
  void CountChunk(uint64_t incarnation, bool accepted, int64_t policy_version = -1);
  // Forgets workers silent for longer than `timeout`; returns their incarnations.
  std::vector<uint64_t> Expire(Clock::time_point now, std::chrono::duration<double> timeout);
  void Remove(uint64_t incarnation);
  // Live workers sorted by slot.
  std::vector<WorkerInfo> Live() const;

 private:
  const RegistryLimits limits_;
  mutable std::mutex mu_;
  std::map<uint64_t, WorkerInfo> by_incarnation_;
  uint64_t next_incarnation_;
};

}  // namespace juggle

#endif  // JUGGLE_LEARNER_WORKER_REGISTRY_H_

// The learner's view of its workers: slots, incarnations and heartbeats. A registration gets
// a slot (its worker index: it seeds the worker's envs) and a fresh incarnation id; a new
// registration for an occupied slot replaces the old incarnation (a restarted worker).
// Thread-safe.
#ifndef JUGGLE_LEARNER_WORKER_REGISTRY_H_
#define JUGGLE_LEARNER_WORKER_REGISTRY_H_

#include <chrono>
#include <cstdint>
#include <map>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

namespace juggle {

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
};

class WorkerRegistry {
 public:
  using Clock = std::chrono::steady_clock;
  // `epoch` makes incarnation ids unique across learner restarts (high 32 bits).
  explicit WorkerRegistry(uint32_t epoch) : next_incarnation_(uint64_t(epoch) << 32 | 1) {}

  // requested_slot < 0: the lowest free slot. Returns the new record; `replaced` receives the
  // incarnation that held the slot before, if any.
  WorkerInfo Register(int requested_slot, int num_envs, const std::string& host,
                      Clock::time_point now, std::optional<uint64_t>* replaced);
  // Records a sign of life. False if the incarnation is unknown.
  bool Touch(uint64_t incarnation, Clock::time_point now, int64_t policy_version = -1,
             double env_steps_per_s = -1);
  std::optional<WorkerInfo> Find(uint64_t incarnation) const;
  // Counts a chunk of `incarnation` as accepted or rejected (unknown incarnations: ignored).
  void CountChunk(uint64_t incarnation, bool accepted);
  // Forgets workers silent for longer than `timeout`; returns their incarnations.
  std::vector<uint64_t> Expire(Clock::time_point now, std::chrono::duration<double> timeout);
  void Remove(uint64_t incarnation);
  // Live workers sorted by slot.
  std::vector<WorkerInfo> Live() const;

 private:
  mutable std::mutex mu_;
  std::map<uint64_t, WorkerInfo> by_incarnation_;
  uint64_t next_incarnation_;
};

}  // namespace juggle

#endif  // JUGGLE_LEARNER_WORKER_REGISTRY_H_

// The current policy snapshot (version, serialized flat parameters, adaptive-walk edge counts)
// and waiting for a newer one. Published by the training thread, read by RPC handlers.
// Thread-safe.
#ifndef JUGGLE_LEARNER_POLICY_STORE_H_
#define JUGGLE_LEARNER_POLICY_STORE_H_

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

namespace juggle {

struct PolicySnapshot {
  int64_t version = 0;
  std::string params;              // FlatParameters::Serialize()
  std::vector<double> edge_counts;
};

class PolicyStore {
 public:
  void Publish(std::shared_ptr<const PolicySnapshot> snapshot);
  std::shared_ptr<const PolicySnapshot> Current() const;
  // The first snapshot with version > min_version, or the current one at the deadline or
  // after Close().
  std::shared_ptr<const PolicySnapshot> WaitNewer(int64_t min_version,
                                                  std::chrono::steady_clock::time_point deadline) const;
  void Close();

 private:
  mutable std::mutex mu_;
  mutable std::condition_variable cv_;
  std::shared_ptr<const PolicySnapshot> current_;
  bool closed_ = false;
};

}  // namespace juggle

#endif  // JUGGLE_LEARNER_POLICY_STORE_H_

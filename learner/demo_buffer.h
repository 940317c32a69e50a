// The learner's demonstration buffer (planner-guided training, docs/learning.md): the newest
// `capacity` (observation, expert label) pairs from the labelled unrolls of the batches (and
// from offline demonstrations, AddAll), oldest out. Memory grows to capacity × (obs_dim + act_dim) floats and then stays flat. Its
// accounts reconcile: added = size + evicted. It is saved beside the checkpoints
// (Serialize/Parse) so that a resumed run keeps its labels. Thread-compatible.
#ifndef JUGGLE_LEARNER_DEMO_BUFFER_H_
#define JUGGLE_LEARNER_DEMO_BUFFER_H_

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "absl/status/statusor.h"
#include "common/unroll_batch.h"

namespace juggle {

class DemoBuffer {
 public:
  DemoBuffer(int64_t capacity, int obs_dim, int act_dim);

  // Adds every step of `batch`'s labelled unrolls (REQUIRES: a validated batch of these dims);
  // returns the pairs added.
  int64_t AddLabelled(const UnrollBatch& batch);
  // Adds n pairs, row i from obs[i·obs_dim ..] and labels[i·act_dim ..], in row order (tools
  // that make demonstrations outside a batch); returns n.
  int64_t AddPairs(const float* obs, const float* labels, int64_t n);
  // Adds every pair of `other` in the order it was added (its oldest first; a smaller buffer
  // keeps the newest); returns the pairs added. INVALID_ARGUMENT for other dims or itself.
  absl::StatusOr<int64_t> AddAll(const DemoBuffer& other);

  int64_t size() const { return size_; }
  int64_t capacity() const { return capacity_; }
  int64_t added() const { return added_; }
  int64_t evicted() const { return added_ - size_; }
  // The row of the oldest pair (rows oldest..size−1, then 0..oldest−1 are in the order added).
  int64_t oldest() const { return size_ < capacity_ ? 0 : next_; }
  // Row-major [size, obs_dim] and [size, act_dim], row i of one matching row i of the other
  // (a ring: oldest() gives the order they were added in).
  const float* obs() const { return obs_.data(); }
  const float* labels() const { return labels_.data(); }
  // Per action: the variance of the labels it holds (population; 0 when empty).
  std::vector<double> LabelVariance() const;
  int obs_dim() const { return obs_dim_; }
  int act_dim() const { return act_dim_; }

  // The whole buffer as bytes: "JGLDEMO1", capacity, dims, size, next, added (int64, little
  // endian as in memory), then the observations and labels (float32).
  std::string Serialize() const;
  // A buffer from Serialize's bytes. INVALID_ARGUMENT for bytes that are not a buffer (magic,
  // sizes, length) or whose capacity or dims differ from the given ones (a changed config).
  static absl::StatusOr<DemoBuffer> Parse(std::string_view bytes, int64_t capacity, int obs_dim,
                                          int act_dim);
  // The same, taking capacity and dims from the bytes (tools that read any saved buffer).
  static absl::StatusOr<DemoBuffer> Parse(std::string_view bytes);

 private:
  void AddRow(const float* obs, const float* label);

  int64_t capacity_;
  int obs_dim_, act_dim_;
  std::vector<float> obs_, labels_;
  int64_t size_ = 0;
  int64_t next_ = 0;  // the row the next pair goes to once full
  int64_t added_ = 0;
  std::vector<double> label_sum_, label_sum_sq_;  // per action, over the rows held
};

}  // namespace juggle

#endif  // JUGGLE_LEARNER_DEMO_BUFFER_H_

#include "learner/demo_buffer.h"

#include <algorithm>

namespace juggle {

DemoBuffer::DemoBuffer(int64_t capacity, int obs_dim, int act_dim)
    : capacity_(std::max<int64_t>(1, capacity)),
      obs_dim_(obs_dim),
      act_dim_(act_dim),
      label_sum_(act_dim, 0.0),
      label_sum_sq_(act_dim, 0.0) {}

std::vector<double> DemoBuffer::LabelVariance() const {
  std::vector<double> var(act_dim_, 0.0);
  if (size_ == 0) return var;
  for (int a = 0; a < act_dim_; ++a) {
    const double mean = label_sum_[a] / size_;
    var[a] = std::max(0.0, label_sum_sq_[a] / size_ - mean * mean);
  }
  return var;
}

int64_t DemoBuffer::AddLabelled(const UnrollBatch& b) {
  if (!b.has_labels()) return 0;
  if (obs_.capacity() == 0) {  // once: the whole bound, so memory stays flat from here
    obs_.reserve(capacity_ * obs_dim_);
    labels_.reserve(capacity_ * act_dim_);
  }
  const int64_t T = b.unroll_length;
  int64_t row = 0, n = 0;  // label row of the current labelled unroll; pairs added
  for (int u = 0; u < b.num_unrolls; ++u) {
    if (!b.labelled[u]) continue;
    for (int64_t t = 0; t < T; ++t) {
      const float* o = &b.obs[(u * T + t) * obs_dim_];
      const float* l = &b.labels[(row * T + t) * act_dim_];
      int64_t at;
      if (size_ < capacity_) {
        at = size_++;
        obs_.resize(size_ * obs_dim_);
        labels_.resize(size_ * act_dim_);
      } else {
        at = next_;
        next_ = (next_ + 1) % capacity_;
        for (int a = 0; a < act_dim_; ++a) {  // the evicted row leaves the sums
          const double x = labels_[at * act_dim_ + a];
          label_sum_[a] -= x;
          label_sum_sq_[a] -= x * x;
        }
      }
      for (int a = 0; a < act_dim_; ++a) {
        label_sum_[a] += l[a];
        label_sum_sq_[a] += double(l[a]) * l[a];
      }
      std::copy(o, o + obs_dim_, obs_.begin() + at * obs_dim_);
      std::copy(l, l + act_dim_, labels_.begin() + at * act_dim_);
      ++n;
    }
    ++row;
  }
  added_ += n;
  return n;
}

}  // namespace juggle

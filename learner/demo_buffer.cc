#include "learner/demo_buffer.h"

#include <algorithm>
#include <cstring>

#include "absl/strings/str_cat.h"

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

void DemoBuffer::AddRow(const float* o, const float* l) {
  if (obs_.capacity() == 0) {  // once: the whole bound, so memory stays flat from here
    obs_.reserve(capacity_ * obs_dim_);
    labels_.reserve(capacity_ * act_dim_);
  }
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
  ++added_;
}

int64_t DemoBuffer::AddLabelled(const UnrollBatch& b) {
  if (!b.has_labels()) return 0;
  const int64_t T = b.unroll_length;
  int64_t row = 0, n = 0;  // label row of the current labelled unroll; pairs added
  for (int u = 0; u < b.num_unrolls; ++u) {
    if (!b.labelled[u]) continue;
    for (int64_t t = 0; t < T; ++t) {
      AddRow(&b.obs[(u * T + t) * obs_dim_], &b.labels[(row * T + t) * act_dim_]);
      ++n;
    }
    ++row;
  }
  return n;
}

int64_t DemoBuffer::AddPairs(const float* obs, const float* labels, int64_t n) {
  for (int64_t i = 0; i < n; ++i) AddRow(obs + i * obs_dim_, labels + i * act_dim_);
  return n;
}

absl::StatusOr<int64_t> DemoBuffer::AddAll(const DemoBuffer& other) {
  if (&other == this) return absl::InvalidArgumentError("a buffer cannot add itself");
  if (other.obs_dim_ != obs_dim_ || other.act_dim_ != act_dim_) {
    return absl::InvalidArgumentError(absl::StrCat(
        "the demonstrations hold ", other.obs_dim_, " observations and ", other.act_dim_,
        " actions per state; this buffer holds ", obs_dim_, " and ", act_dim_));
  }
  for (int64_t i = 0; i < other.size_; ++i) {
    const int64_t r = (other.oldest() + i) % other.size_;
    AddRow(&other.obs_[r * obs_dim_], &other.labels_[r * act_dim_]);
  }
  return other.size_;
}

namespace {

constexpr char kMagic[8] = {'J', 'G', 'L', 'D', 'E', 'M', 'O', '1'};
constexpr size_t kHeader = sizeof(kMagic) + 6 * sizeof(int64_t);

}  // namespace

std::string DemoBuffer::Serialize() const {
  const int64_t header[6] = {capacity_, obs_dim_, act_dim_, size_, next_, added_};
  std::string out(kMagic, sizeof(kMagic));
  out.append(reinterpret_cast<const char*>(header), sizeof(header));
  out.append(reinterpret_cast<const char*>(obs_.data()), size_ * obs_dim_ * sizeof(float));
  out.append(reinterpret_cast<const char*>(labels_.data()), size_ * act_dim_ * sizeof(float));
  return out;
}

absl::StatusOr<DemoBuffer> DemoBuffer::Parse(std::string_view bytes) {
  if (bytes.size() < kHeader || std::memcmp(bytes.data(), kMagic, sizeof(kMagic)) != 0) {
    return absl::InvalidArgumentError("not a demonstration buffer (bad magic or too short)");
  }
  int64_t h[3];
  std::memcpy(h, bytes.data() + sizeof(kMagic), sizeof(h));
  // The capacity's bound is imitation.buffer_size's (proto/imitation.proto).
  if (h[0] < 1 || h[0] > 100000000 || h[1] < 1 || h[1] > 1000000 || h[2] < 1 ||
      h[2] > 1000000) {
    return absl::InvalidArgumentError("the demonstration buffer's sizes are out of range");
  }
  return Parse(bytes, h[0], static_cast<int>(h[1]), static_cast<int>(h[2]));
}

absl::StatusOr<DemoBuffer> DemoBuffer::Parse(std::string_view bytes, int64_t capacity,
                                             int obs_dim, int act_dim) {
  if (bytes.size() < kHeader || std::memcmp(bytes.data(), kMagic, sizeof(kMagic)) != 0) {
    return absl::InvalidArgumentError("not a demonstration buffer (bad magic or too short)");
  }
  int64_t h[6];
  std::memcpy(h, bytes.data() + sizeof(kMagic), sizeof(h));
  const int64_t cap = h[0], size = h[3], next = h[4], added = h[5];
  if (cap != std::max<int64_t>(1, capacity) || h[1] != obs_dim || h[2] != act_dim) {
    return absl::InvalidArgumentError(absl::StrCat(
        "the saved demonstration buffer holds ", cap, " pairs of ", h[1], " observations and ",
        h[2], " actions; this run's holds ", capacity, " of ", obs_dim, " and ", act_dim));
  }
  if (size < 0 || size > cap || next < 0 || next >= cap || added < size ||
      (size < cap && next != 0)) {
    return absl::InvalidArgumentError("the demonstration buffer's counts are inconsistent");
  }
  const size_t expected = kHeader + size * (obs_dim + act_dim) * sizeof(float);
  if (bytes.size() != expected) {
    return absl::InvalidArgumentError(absl::StrCat("the demonstration buffer is ", bytes.size(),
                                                   " bytes; its header says ", expected));
  }
  DemoBuffer b(capacity, obs_dim, act_dim);
  b.obs_.reserve(cap * obs_dim);
  b.labels_.reserve(cap * act_dim);
  b.obs_.resize(size * obs_dim);
  b.labels_.resize(size * act_dim);
  std::memcpy(b.obs_.data(), bytes.data() + kHeader, b.obs_.size() * sizeof(float));
  std::memcpy(b.labels_.data(), bytes.data() + kHeader + b.obs_.size() * sizeof(float),
              b.labels_.size() * sizeof(float));
  b.size_ = size;
  b.next_ = next;
  b.added_ = added;
  for (int64_t r = 0; r < size; ++r) {
    for (int a = 0; a < act_dim; ++a) {
      const double x = b.labels_[r * act_dim + a];
      b.label_sum_[a] += x;
      b.label_sum_sq_[a] += x * x;
    }
  }
  return b;
}

}  // namespace juggle

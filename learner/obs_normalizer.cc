#include "learner/obs_normalizer.h"

#include <algorithm>
#include <cmath>
#include <cstring>

namespace juggle {

ObsNormalizer::ObsNormalizer(int dim) : mean_(dim, 0.0), m2_(dim, 0.0) {}

void ObsNormalizer::Update(const float* obs, int64_t count) {
  if (count <= 0) return;
  const int d = dim();
  std::vector<double> batch_mean(d, 0.0), batch_m2(d, 0.0);
  for (int64_t i = 0; i < count; ++i) {
    for (int j = 0; j < d; ++j) batch_mean[j] += obs[i * d + j];
  }
  for (int j = 0; j < d; ++j) batch_mean[j] /= count;
  for (int64_t i = 0; i < count; ++i) {
    for (int j = 0; j < d; ++j) {
      const double x = obs[i * d + j] - batch_mean[j];
      batch_m2[j] += x * x;
    }
  }
  const double n_a = count_, n_b = count, n = n_a + n_b;
  for (int j = 0; j < d; ++j) {
    const double delta = batch_mean[j] - mean_[j];
    mean_[j] += delta * n_b / n;
    m2_[j] += batch_m2[j] + delta * delta * n_a * n_b / n;
  }
  count_ += count;
}

std::vector<float> ObsNormalizer::Mean() const {
  return std::vector<float>(mean_.begin(), mean_.end());
}

std::vector<float> ObsNormalizer::InvStd() const {
  std::vector<float> inv(dim(), 1.0f);
  if (count_ < 2) return inv;
  for (int j = 0; j < dim(); ++j) {
    inv[j] = static_cast<float>(1.0 / std::max(std::sqrt(m2_[j] / count_), 1e-2));
  }
  return inv;
}

std::string ObsNormalizer::Serialize() const {
  std::string out;
  const int64_t d = dim();
  out.append(reinterpret_cast<const char*>(&d), sizeof(d));
  out.append(reinterpret_cast<const char*>(&count_), sizeof(count_));
  out.append(reinterpret_cast<const char*>(mean_.data()), d * sizeof(double));
  out.append(reinterpret_cast<const char*>(m2_.data()), d * sizeof(double));
  return out;
}

absl::StatusOr<ObsNormalizer> ObsNormalizer::Deserialize(const std::string& bytes) {
  int64_t d = 0, count = 0;
  if (bytes.size() < 2 * sizeof(int64_t)) return absl::DataLossError("normalizer: truncated");
  std::memcpy(&d, bytes.data(), sizeof(d));
  std::memcpy(&count, bytes.data() + sizeof(d), sizeof(count));
  if (d < 0 || bytes.size() != 2 * sizeof(int64_t) + 2 * size_t(d) * sizeof(double)) {
    return absl::DataLossError("normalizer: wrong size");
  }
  ObsNormalizer n(static_cast<int>(d));
  n.count_ = count;
  std::memcpy(n.mean_.data(), bytes.data() + 16, d * sizeof(double));
  std::memcpy(n.m2_.data(), bytes.data() + 16 + d * sizeof(double), d * sizeof(double));
  return n;
}

}  // namespace juggle

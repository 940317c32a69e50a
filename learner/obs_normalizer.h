// Running mean and variance of observations (Chan et al. parallel update, float64), owned by
// the learner. Its statistics travel to workers inside the flat policy parameters.
// Thread-compatible.
#ifndef JUGGLE_LEARNER_OBS_NORMALIZER_H_
#define JUGGLE_LEARNER_OBS_NORMALIZER_H_

#include <cstdint>
#include <string>
#include <vector>

#include "absl/status/statusor.h"

namespace juggle {

class ObsNormalizer {
 public:
  explicit ObsNormalizer(int dim = 0);
  // Adds `count` observations [count, dim].
  void Update(const float* obs, int64_t count);
  // Per-dimension mean and 1/max(std, 1e-2) as float32.
  std::vector<float> Mean() const;
  std::vector<float> InvStd() const;
  int64_t count() const { return count_; }
  int dim() const { return static_cast<int>(mean_.size()); }

  std::string Serialize() const;
  static absl::StatusOr<ObsNormalizer> Deserialize(const std::string& bytes);

 private:
  std::vector<double> mean_, m2_;
  int64_t count_ = 0;
};

}  // namespace juggle

#endif  // JUGGLE_LEARNER_OBS_NORMALIZER_H_

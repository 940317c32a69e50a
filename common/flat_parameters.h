// Versioned flat parameters with a layout descriptor (names, shapes, dtype float32): the form
// in which the learner exports a policy, the wire carries it, and workers load it.
// Immutable after construction; thread-safe to read.
#ifndef JUGGLE_COMMON_FLAT_PARAMETERS_H_
#define JUGGLE_COMMON_FLAT_PARAMETERS_H_

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "absl/status/statusor.h"
#include "common/network_layout.h"

namespace juggle {

class FlatParameters {
 public:
  FlatParameters() = default;
  // INVALID_ARGUMENT unless values.size() equals the layout's total element count.
  static absl::StatusOr<FlatParameters> Create(int64_t version, std::vector<TensorSpec> layout,
                                               std::vector<float> values);

  int64_t version() const { return version_; }
  const std::vector<TensorSpec>& layout() const { return layout_; }
  const std::vector<float>& values() const { return values_; }

  // The values of tensor `name`. NOT_FOUND if absent; INVALID_ARGUMENT if its shape differs.
  absl::StatusOr<const float*> Find(const std::string& name,
                                    const std::vector<int64_t>& shape) const;

  // Binary form: magic "JGLP", format 1, version, layout, then float32 values (little endian).
  std::string Serialize() const;
  // DATA_LOSS for truncated or malformed input.
  static absl::StatusOr<FlatParameters> Deserialize(std::string_view bytes);

 private:
  int64_t version_ = 0;
  std::vector<TensorSpec> layout_;
  std::vector<int64_t> offsets_;
  std::vector<float> values_;
};

}  // namespace juggle

#endif  // JUGGLE_COMMON_FLAT_PARAMETERS_H_

// libFuzzer: any bytes as a policy snapshot (FlatParameters::Deserialize, what a worker does
// with GetPolicy's data). Invariant: a parsed snapshot's layout accounts for every value, and
// it serializes back to the same bytes.
#include <cstdint>
#include <cstdlib>
#include <string_view>

#include "common/flat_parameters.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  absl::StatusOr<juggle::FlatParameters> params = juggle::FlatParameters::Deserialize(bytes);
  if (!params.ok()) return 0;
  int64_t expected = 0;
  for (const juggle::TensorSpec& t : params->layout()) expected += t.numel();
  if (expected != static_cast<int64_t>(params->values().size())) std::abort();
  if (params->Serialize() != bytes) std::abort();
  return 0;
}

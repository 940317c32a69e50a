// libFuzzer: any text as a run config (configs/*.textproto) through parsing, the schema's range
// checks and the family's validation, as if it were configs/fuzz.textproto (so the graph and
// model paths of the shipped configs resolve). Must return a status, never crash or hang.
#include <cstdint>
#include <string>

#include "envs/registry.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  absl::StatusOr<juggle::LoadedConfig> loaded = juggle::ParseRunConfig(text, "configs/fuzz.textproto");
  (void)loaded;
  return 0;
}

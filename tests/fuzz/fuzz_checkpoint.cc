// libFuzzer: any bytes as a checkpoint file (ParseCheckpoint, what ReadCheckpointFile and
// --resume use). Invariant: a parsed checkpoint's sections fit in the bytes it came from.
#include <cstdint>
#include <cstdlib>
#include <string>

#include "learner/checkpoint.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string bytes(reinterpret_cast<const char*>(data), size);
  absl::StatusOr<juggle::Sections> sections = juggle::ParseCheckpoint(bytes, "fuzz.jglc");
  if (!sections.ok()) return 0;
  size_t total = 0;
  for (const auto& [name, body] : *sections) total += name.size() + body.size();
  if (total > size) std::abort();
  return 0;
}

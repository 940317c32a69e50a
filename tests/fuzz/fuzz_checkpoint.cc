// libFuzzer: any bytes as a checkpoint file (ParseCheckpoint, what ReadCheckpointFile and
// --resume use), once as they are and once as the payload of a file with a correct header and
// checksum (so the section table is reached, not only the checksum test). Invariant: a parsed
// checkpoint's sections fit in the bytes they came from.
#include <cstdint>
#include <cstdlib>
#include <string>

#include "learner/checkpoint.h"

namespace {

void ParseAndCheck(const std::string& bytes) {
  absl::StatusOr<juggle::Sections> sections = juggle::ParseCheckpoint(bytes, "fuzz.jglc");
  if (!sections.ok()) return;
  size_t total = 0;
  for (const auto& [name, body] : *sections) total += name.size() + body.size();
  if (total > bytes.size()) std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string bytes(reinterpret_cast<const char*>(data), size);
  ParseAndCheck(bytes);
  std::string file = "JGLCKPT1";
  const uint64_t length = bytes.size(), checksum = juggle::Fnv1a64(bytes);
  file.append(reinterpret_cast<const char*>(&length), sizeof(length));
  file.append(reinterpret_cast<const char*>(&checksum), sizeof(checksum));
  ParseAndCheck(file + bytes);
  return 0;
}

// libFuzzer: any bytes as an exported-policy file (ParsePolicyFile, what `eval`, `render`,
// `toss`, `export-policy` and toss loop configs read), once as they are (format 1 or a format-2
// header) and once as the payload of a format-2 file with a correct header and checksum (so the
// payload's parsing and completeness checks are reached). Invariants: a parsed policy's byte
// fields fit in the bytes they came from (the message as a whole may re-serialize longer: a
// negative int32 written in fewer than 10 bytes), and a format-2 file has every part it requires.
#include <cstdint>
#include <cstdlib>
#include <string>

#include "common/checksum.h"
#include "common/policy_file.h"

namespace {

void ParseAndCheck(const std::string& bytes) {
  absl::StatusOr<juggle::PolicyFile> file = juggle::ParsePolicyFile(bytes, "fuzz.jglpolicy");
  if (!file.ok()) return;
  const juggle::config::ExportedPolicy& p = file->policy;
  const size_t held = p.parameters().size() + p.run_config().size() + p.model_mjb().size() +
                      p.source().size() + p.config_path().size();
  if (held > bytes.size()) std::abort();
  if (file->format == 2 && (p.parameters().empty() || p.model_mjb().empty() ||
                            p.run_config().empty() || p.obs_dim() <= 0 || p.act_dim() <= 0)) {
    std::abort();
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string bytes(reinterpret_cast<const char*>(data), size);
  ParseAndCheck(bytes);
  std::string file = "JGLPOLCY";
  const uint32_t format = 2;
  const uint64_t length = bytes.size(), checksum = juggle::Fnv1a64(bytes);
  file.append(reinterpret_cast<const char*>(&format), sizeof(format));
  file.append(reinterpret_cast<const char*>(&length), sizeof(length));
  file.append(reinterpret_cast<const char*>(&checksum), sizeof(checksum));
  ParseAndCheck(file + bytes);
  return 0;
}

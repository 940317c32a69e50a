#include "common/policy_file.h"

#include <cstdint>
#include <cstring>

#include "absl/strings/str_cat.h"
#include "common/checksum.h"
#include "common/file_io.h"

namespace juggle {
namespace {

constexpr char kPolicyMagic[8] = {'J', 'G', 'L', 'P', 'O', 'L', 'C', 'Y'};
constexpr size_t kHeaderSize = sizeof(kPolicyMagic) + sizeof(uint32_t) + 2 * sizeof(uint64_t);
constexpr char kHowToWrite[] = "write one with `juggle export-policy`";

template <typename T>
void PutRaw(std::string* out, T v) {
  out->append(reinterpret_cast<const char*>(&v), sizeof(T));
}

template <typename T>
T GetRaw(std::string_view in, size_t pos) {
  T v;
  std::memcpy(&v, in.data() + pos, sizeof(T));
  return v;
}

// The first part format 2 requires that `policy` lacks, or "" if it is complete.
std::string MissingPart(const config::ExportedPolicy& policy) {
  if (policy.parameters().empty()) return "parameters";
  if (policy.obs_dim() <= 0 || policy.act_dim() <= 0) return "observation and action sizes";
  if (policy.run_config().empty()) return "run config";
  if (policy.model_mjb().empty()) return "compiled model";
  return "";
}

absl::StatusOr<PolicyFile> ParseFormat1(std::string_view bytes, const std::string& path) {
  PolicyFile file;
  file.format = 1;
  if (!file.policy.ParseFromArray(bytes.data(), static_cast<int>(bytes.size())) ||
      file.policy.parameters().empty()) {
    return absl::DataLossError(
        absl::StrCat(path, ": not an exported policy (", kHowToWrite, ")"));
  }
  return file;
}

}  // namespace

std::string SerializePolicyFile(const config::ExportedPolicy& policy) {
  const std::string payload = policy.SerializeAsString();
  std::string file(kPolicyMagic, sizeof(kPolicyMagic));
  PutRaw<uint32_t>(&file, kPolicyFileFormat);
  PutRaw<uint64_t>(&file, payload.size());
  PutRaw<uint64_t>(&file, Fnv1a64(payload));
  file += payload;
  return file;
}

absl::StatusOr<PolicyFile> ParsePolicyFile(std::string_view bytes, const std::string& path) {
  if (bytes.size() < sizeof(kPolicyMagic) ||
      std::memcmp(bytes.data(), kPolicyMagic, sizeof(kPolicyMagic)) != 0) {
    return ParseFormat1(bytes, path);
  }
  auto loss = [&](const std::string& what) {
    return absl::DataLossError(absl::StrCat(path, ": exported policy ", what));
  };
  if (bytes.size() < kHeaderSize) return loss("truncated in its header");
  const uint32_t format = GetRaw<uint32_t>(bytes, sizeof(kPolicyMagic));
  if (format > kPolicyFileFormat) {
    return absl::FailedPreconditionError(absl::StrCat(
        path, ": exported policy of format ", format, ", written by a newer juggle (this one "
        "reads formats 1 to ", kPolicyFileFormat, ")"));
  }
  if (format != kPolicyFileFormat) return loss(absl::StrCat("of unknown format ", format));
  const uint64_t size = GetRaw<uint64_t>(bytes, sizeof(kPolicyMagic) + sizeof(uint32_t));
  const uint64_t checksum = GetRaw<uint64_t>(bytes, sizeof(kPolicyMagic) + sizeof(uint32_t) + 8);
  const std::string_view payload = bytes.substr(kHeaderSize);
  if (payload.size() != size) {
    return loss(absl::StrCat("truncated or padded: its payload has ", payload.size(), " of ",
                             size, " bytes"));
  }
  if (Fnv1a64(payload) != checksum) return loss("corrupted: checksum mismatch");
  PolicyFile file;
  file.format = format;
  if (!file.policy.ParseFromArray(payload.data(), static_cast<int>(payload.size()))) {
    return loss("corrupted: its payload does not parse");
  }
  if (const std::string missing = MissingPart(file.policy); !missing.empty()) {
    return loss(absl::StrCat("incomplete: it has no ", missing));
  }
  return file;
}

absl::StatusOr<PolicyFile> ReadPolicyFile(const std::string& path) {
  absl::StatusOr<std::string> bytes = ReadFile(path);
  if (!bytes.ok()) return bytes.status();
  return ParsePolicyFile(*bytes, path);
}

absl::Status WritePolicyFile(const std::string& path, const config::ExportedPolicy& policy) {
  if (const std::string missing = MissingPart(policy); !missing.empty()) {
    return absl::InvalidArgumentError(absl::StrCat(
        path, ": cannot write an exported policy without its ", missing));
  }
  return WriteFileAtomically(path, SerializePolicyFile(policy));
}

}  // namespace juggle

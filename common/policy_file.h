// Exported-policy files (.jglpolicy, `juggle export-policy`): the container around a
// config::ExportedPolicy (proto/policy.proto). Torch-free and MuJoCo-free: this reads and checks
// bytes; envs/stored_config.h turns a file's config into a LoadedConfig.
//
// Formats, told apart by the first bytes:
//   1  (files written before format 2) the bare ExportedPolicy protobuf. Its run_config names
//      the MuJoCo model relative to config_path, so it loads only from the folder it was
//      exported in.
//   2  "JGLPOLCY" (8 bytes), uint32 format (2), uint64 payload size, uint64 FNV-1a 64 of the
//      payload (common/checksum.h), then the payload: an ExportedPolicy with parameters, sizes,
//      run_config and model_mjb. Self-contained: loading it reads no other file.
// Integers are little-endian (the only byte order the project builds for, as checkpoints).
#ifndef JUGGLE_COMMON_POLICY_FILE_H_
#define JUGGLE_COMMON_POLICY_FILE_H_

#include <string>
#include <string_view>

#include "absl/status/status.h"
#include "absl/status/statusor.h"
#include "proto/policy.pb.h"

namespace juggle {

// The format WritePolicyFile writes.
inline constexpr int kPolicyFileFormat = 2;

struct PolicyFile {
  config::ExportedPolicy policy;
  int format = 0;  // 1 or 2 (see above)
};

// The bytes of a format-2 file holding `policy` (which WritePolicyFile checks first).
std::string SerializePolicyFile(const config::ExportedPolicy& policy);

// Parses a policy file's `bytes`; `path` names them in errors. Every error names `path`:
// DATA_LOSS when the bytes are not a policy, are truncated (the header's size is compared with
// what is there before anything is copied), fail the checksum, or lack a part their format
// requires (format 1: parameters; format 2: parameters, sizes, run_config and model_mjb);
// FAILED_PRECONDITION for a format newer than kPolicyFileFormat.
absl::StatusOr<PolicyFile> ParsePolicyFile(std::string_view bytes, const std::string& path);

// Reads and parses `path`: ReadFile's errors (NOT_FOUND, ...) or ParsePolicyFile's.
absl::StatusOr<PolicyFile> ReadPolicyFile(const std::string& path);

// Writes `policy` as a format-2 file, atomically. INVALID_ARGUMENT (naming `path`) when the
// policy lacks a part format 2 requires; I/O errors as WriteFileAtomically.
absl::Status WritePolicyFile(const std::string& path, const config::ExportedPolicy& policy);

}  // namespace juggle

#endif  // JUGGLE_COMMON_POLICY_FILE_H_

// Where the policy-running commands (eval, render, toss, export-policy) get a policy: a
// checkpoint file (.jglc), a run directory (its newest readable checkpoint) or an exported
// policy (.jglpolicy, torch-free), each with the run config it was trained with.
#ifndef JUGGLE_APP_POLICY_SOURCE_H_
#define JUGGLE_APP_POLICY_SOURCE_H_

#include <memory>
#include <string>

#include "absl/status/statusor.h"
#include "common/config_loader.h"
#include "common/eigen_policy.h"

namespace juggle {

struct PolicySource {
  LoadedConfig config;
  std::shared_ptr<const EigenPolicy> policy;
  config::ExportedPolicy exported;  // the policy in exportable form
  std::string path;                 // the file it was read from
};

// Loads `path`. `config_path`, if not empty, replaces the config recorded with the policy
// (it must describe the same observation and action sizes). Errors: NOT_FOUND / DATA_LOSS for
// unreadable files, FAILED_PRECONDITION when no config is known, INVALID_ARGUMENT when the
// policy does not fit the config.
absl::StatusOr<PolicySource> LoadPolicySource(const std::string& path,
                                              const std::string& config_path);

}  // namespace juggle

#endif  // JUGGLE_APP_POLICY_SOURCE_H_

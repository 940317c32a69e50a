// Run configs stored inside other files — exported policies (common/policy_file.h), checkpoints
// (learner/learner_state.h) — and sent to workers at Register (proto/rollout.proto): the
// prepared RunConfig as text, with every file it names inlined, and the model compiled from its
// MJCF. Loading one reads no file and compiles nothing, so what it loads does not change when
// the config, graph or model files are edited, moved or deleted, nor with the working folder.
#ifndef JUGGLE_ENVS_STORED_CONFIG_H_
#define JUGGLE_ENVS_STORED_CONFIG_H_

#include <string>

#include "absl/status/statusor.h"
#include "common/config_loader.h"
#include "envs/env.h"

namespace juggle {

struct StoredConfig {
  std::string text;       // LoadedConfig::run in text format (its files already inlined)
  std::string model_mjb;  // mj_saveModel bytes of the env spec's model
};

// The stored form of `config`. REQUIRES: `spec` was made from `config` (CreateEnvSpec).
StoredConfig StoreConfig(const LoadedConfig& config, const EnvSpec& spec);

// Parses `stored` back into a config whose model is pinned to stored.model_mjb (CreateEnvSpec
// loads those bytes). `name` names the text in errors ("file:line:col"); the result's
// config_path is `config_path`, the file the config was first read from, kept for reports
// (nothing is read from it). Errors: INVALID_ARGUMENT when the text names a file to read
// (base_config, or a *_file field other than model_file, which the pinned model replaces) or
// lacks the model, otherwise as ParseRunConfig (a field this build no longer knows, ...).
absl::StatusOr<LoadedConfig> LoadStoredConfig(const StoredConfig& stored, const std::string& name,
                                              const std::string& config_path);

}  // namespace juggle

#endif  // JUGGLE_ENVS_STORED_CONFIG_H_

// The family-independent half of loading configs/*.textproto: text-format parsing with
// file:line:col errors, the checks of the shared sections (sampling, service, ...), and file
// helpers the families use for the files their sections name. envs/registry.h's LoadRunConfig
// runs this and then the family's own checks; callers use that.
#ifndef JUGGLE_COMMON_CONFIG_LOADER_H_
#define JUGGLE_COMMON_CONFIG_LOADER_H_

#include <memory>
#include <string>

#include "absl/status/statusor.h"
#include "common/control_graph.h"
#include "common/file_io.h"  // ReadFile, for the config readers
#include "common/source_locator.h"
#include "google/protobuf/message.h"
#include "proto/run_config.pb.h"

namespace juggle {

struct LoadedConfig {
  config::RunConfig run;          // files named by the family's section already inlined
  std::string config_path;
  std::string config_dir;         // relative paths in the config resolve against this
  SourceLocator root{""};         // locates fields of the RunConfig
  SourceLocator family_locator{""};  // locates fields of the family's section (run.<family>)
  // The control graph the adaptive walk runs on, validated; empty for families without one.
  std::shared_ptr<const ControlGraph> graph = std::make_shared<const ControlGraph>();
  SourceLocator graph_locator{""};  // locates fields of the graph (inline or its own file)
  // The compiled model (mj_saveModel bytes) when the config came stored with it
  // (envs/stored_config.h: exported policies, checkpoints): the env families load these bytes
  // instead of compiling the model_file MJCF. Empty: compile model_file.
  std::string model_mjb;
  // The exported policy (.jglpolicy) this config was read from, if any: recordings name it so
  // that a replay loads the same stored config (envs/policy_config.h, LoadConfigOrPolicy).
  std::string policy_file;
};

// What a recording names as its config (record/trajectory.h): the policy file the config came
// stored in, if any (replays load that stored copy again), else config_path.
inline const std::string& RecordedConfigName(const LoadedConfig& config) {
  return config.policy_file.empty() ? config.config_path : config.policy_file;
}

// Parses `text` (from `path`) into a RunConfig and checks the sections every family shares.
// A `base_config` is loaded first (relative to `path`'s folder, recursively) and this file's
// fields laid over it (common/config_merge.h); errors name the file that set the field, and a
// cycle of bases is refused naming the chain. The family's own section is left unchecked.
// INVALID_ARGUMENT "file:line:col: ..." for syntax errors, unknown fields and out-of-range
// shared fields; NOT_FOUND for a base that cannot be read.
absl::StatusOr<LoadedConfig> ParseSharedRunConfig(const std::string& text, const std::string& path);

// Parses text-format `text` into `message`, returning a locator over it. INVALID_ARGUMENT with
// "file:line:col: message" lines.
absl::StatusOr<SourceLocator> ParseTextMessage(const std::string& text, const std::string& path,
                                               google::protobuf::Message* message);

// Reads a config file: as ReadFile (common/file_io.h), and INVALID_ARGUMENT for a directory ("<path> is a
// directory, not a config file").
absl::StatusOr<std::string> ReadConfigFile(const std::string& path);

// Resolves `relative` against `dir` unless it is absolute.
std::string ResolvePath(const std::string& dir, const std::string& relative);

}  // namespace juggle

#endif  // JUGGLE_COMMON_CONFIG_LOADER_H_

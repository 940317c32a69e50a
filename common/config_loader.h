// Loads configs/*.textproto into a typed RunConfig and validates it. Errors name the file,
// line, column and field; on error nothing is returned, so nothing can start half-configured.
#ifndef JUGGLE_COMMON_CONFIG_LOADER_H_
#define JUGGLE_COMMON_CONFIG_LOADER_H_

#include <memory>
#include <string>

#include "absl/status/statusor.h"
#include "common/control_graph.h"
#include "common/source_locator.h"
#include "proto/run_config.pb.h"

namespace juggle {

struct LoadedConfig {
  config::RunConfig run;          // graph_file already resolved into run.graph
  std::string config_path;
  std::string config_dir;         // relative paths in the config resolve against this
  std::shared_ptr<const ControlGraph> graph;  // validated
  // Locates fields of run.env, or of run.toss for a toss config (for model-dependent checks).
  SourceLocator env_locator{""};
  SourceLocator graph_locator{""};  // locates fields of the graph (either file)
};

// Reads and validates a RunConfig file. Errors: NOT_FOUND (missing file), INVALID_ARGUMENT
// (syntax, unknown fields, semantic checks), each message starting with "file:line:col".
absl::StatusOr<LoadedConfig> LoadRunConfig(const std::string& path);

// As LoadRunConfig, from text; `path` names the text in messages and anchors relative paths.
absl::StatusOr<LoadedConfig> ParseRunConfig(const std::string& text, const std::string& path);

// Reads a whole file. NOT_FOUND if it cannot be opened.
absl::StatusOr<std::string> ReadFile(const std::string& path);

// Resolves `relative` against `dir` unless it is absolute.
std::string ResolvePath(const std::string& dir, const std::string& relative);

}  // namespace juggle

#endif  // JUGGLE_COMMON_CONFIG_LOADER_H_

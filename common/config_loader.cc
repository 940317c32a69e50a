#include "common/config_loader.h"

#include <fstream>
#include <sstream>

#include "absl/strings/str_cat.h"
#include "common/status_macros.h"
#include "google/protobuf/io/tokenizer.h"
#include "google/protobuf/text_format.h"

namespace juggle {
namespace {

using google::protobuf::Message;
using google::protobuf::TextFormat;

// Collects TextFormat errors as "file:line:col: message".
class ErrorCollector : public google::protobuf::io::ErrorCollector {
 public:
  explicit ErrorCollector(std::string file) : file_(std::move(file)) {}
  void AddError(int line, int column, const std::string& message) override {
    if (!errors_.empty()) errors_ += "\n";
    absl::StrAppend(&errors_, file_, ":", line + 1, ":", column + 1, ": ", message);
  }
  void AddWarning(int line, int column, const std::string& message) override {
    AddError(line, column, message);  // warnings are errors for configs
  }
  const std::string& errors() const { return errors_; }

 private:
  std::string file_;
  std::string errors_;
};

// Parses `text` into `message`, returning a locator over it.
absl::StatusOr<SourceLocator> ParseText(const std::string& text, const std::string& path,
                                        Message* message) {
  ErrorCollector errors(path);
  auto tree = std::make_unique<TextFormat::ParseInfoTree>();
  TextFormat::Parser parser;
  parser.RecordErrorsTo(&errors);
  parser.WriteLocationsTo(tree.get());
  parser.AllowUnknownField(false);
  if (!parser.ParseFromString(text, message) || !errors.errors().empty()) {
    return absl::InvalidArgumentError(errors.errors().empty()
                                          ? absl::StrCat(path, ": could not parse")
                                          : errors.errors());
  }
  return SourceLocator(path, message->GetDescriptor(), std::move(tree));
}

std::string DirName(const std::string& path) {
  const size_t slash = path.rfind('/');
  return slash == std::string::npos ? "." : path.substr(0, slash);
}

absl::Status ValidateEnv(const config::EnvConfig& env, const SourceLocator& where) {
  if (env.sim_dt() <= 0) {
    return absl::InvalidArgumentError(absl::StrCat(where.Where({{"sim_dt"}}), ": must be > 0"));
  }
  if (env.substeps() < 1) {
    return absl::InvalidArgumentError(absl::StrCat(where.Where({{"substeps"}}), ": must be >= 1"));
  }
  if (env.max_episode_steps() < 1) {
    return absl::InvalidArgumentError(
        absl::StrCat(where.Where({{"max_episode_steps"}}), ": must be >= 1"));
  }
  if (env.gravity() <= 0) {
    return absl::InvalidArgumentError(absl::StrCat(where.Where({{"gravity"}}), ": must be > 0"));
  }
  return absl::OkStatus();
}

}  // namespace

absl::StatusOr<std::string> ReadFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return absl::NotFoundError(absl::StrCat(path, ": cannot open file"));
  std::stringstream buffer;
  buffer << in.rdbuf();
  return buffer.str();
}

std::string ResolvePath(const std::string& dir, const std::string& relative) {
  if (relative.empty() || relative[0] == '/') return relative;
  return absl::StrCat(dir, "/", relative);
}

absl::StatusOr<LoadedConfig> ParseRunConfig(const std::string& text, const std::string& path) {
  LoadedConfig loaded;
  loaded.config_path = path;
  loaded.config_dir = DirName(path);
  ASSIGN_OR_RETURN(SourceLocator root, ParseText(text, path, &loaded.run));
  loaded.env_locator = root.Nested({{"env"}});
  RETURN_IF_ERROR(ValidateEnv(loaded.run.env(), loaded.env_locator));
  if (loaded.run.sampling().num_envs() < 1 || loaded.run.sampling().num_threads() < 1) {
    return absl::InvalidArgumentError(
        absl::StrCat(root.Where({{"sampling"}}), ": num_envs and num_threads must be >= 1"));
  }

  const bool inline_graph = loaded.run.has_graph();
  const bool file_graph = loaded.run.has_graph_file();
  if (inline_graph == file_graph) {
    return absl::InvalidArgumentError(absl::StrCat(
        root.Where({{inline_graph ? "graph_file" : "graph"}}),
        ": exactly one of 'graph' (inline) or 'graph_file' must be set"));
  }
  if (file_graph) {
    const std::string graph_path = ResolvePath(loaded.config_dir, loaded.run.graph_file());
    absl::StatusOr<std::string> graph_text = ReadFile(graph_path);
    if (!graph_text.ok()) {
      return absl::NotFoundError(absl::StrCat(root.Where({{"graph_file"}}), ": ",
                                              graph_text.status().message()));
    }
    ASSIGN_OR_RETURN(loaded.graph_locator,
                     ParseText(*graph_text, graph_path, loaded.run.mutable_graph()));
  } else {
    loaded.graph_locator = root.Nested({{"graph"}});
  }
  ASSIGN_OR_RETURN(ControlGraph graph, ControlGraph::Build(loaded.run.graph(),
                                                           loaded.graph_locator));
  loaded.graph = std::make_shared<const ControlGraph>(std::move(graph));
  return loaded;
}

absl::StatusOr<LoadedConfig> LoadRunConfig(const std::string& path) {
  ASSIGN_OR_RETURN(std::string text, ReadFile(path));
  return ParseRunConfig(text, path);
}

}  // namespace juggle

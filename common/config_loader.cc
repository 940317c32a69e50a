#include "common/config_loader.h"

#include <sys/stat.h>

#include <filesystem>
#include <vector>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_join.h"
#include "common/config_merge.h"
#include "common/config_ranges.h"
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

std::string DirName(const std::string& path) {
  const size_t slash = path.rfind('/');
  return slash == std::string::npos ? "." : path.substr(0, slash);
}

std::string CanonicalName(const std::string& path) {
  std::error_code ignored;
  const std::filesystem::path canonical = std::filesystem::weakly_canonical(path, ignored);
  return canonical.empty() ? path : canonical.string();
}

// planner.kick and planner.cost moved into the soccer task's block (proto/planner.proto):
// configs, stored configs and checkpoints written before keep loading, with the two blocks moved
// there. INVALID_ARGUMENT naming both places when one file sets one in both.
absl::Status MoveSoccerPlannerFields(const SourceLocator& where, config::RunConfig* run) {
  if (!run->has_planner()) return absl::OkStatus();
  config::PlannerConfig* p = run->mutable_planner();
  if (!p->has_kick() && !p->has_cost()) return absl::OkStatus();
  config::SoccerJugglePlanning* task = p->mutable_soccer_juggle();
  if ((p->has_kick() && task->has_kick()) || (p->has_cost() && task->has_cost())) {
    const char* field = p->has_kick() && task->has_kick() ? "kick" : "cost";
    return absl::InvalidArgumentError(absl::StrCat(
        where.Where({{"planner"}, {field}}), ": set both here and in planner.soccer_juggle.",
        field, "; it belongs in planner.soccer_juggle (docs/planner.md)"));
  }
  if (p->has_kick()) task->mutable_kick()->Swap(p->mutable_kick());
  if (p->has_cost()) task->mutable_cost()->Swap(p->mutable_cost());
  p->clear_kick();
  p->clear_cost();
  return absl::OkStatus();
}

// Parses `text` (from `path`) into `run` and, when it names a base_config, loads that first
// (recursively) and lays this file's fields over it; `where` locates each field in the file
// that set it. `chain`: the files being composed, outermost first (a cycle is an error).
absl::Status ParseComposed(const std::string& text, const std::string& path,
                           std::vector<std::string>* chain, config::RunConfig* run,
                           SourceLocator* where) {
  config::RunConfig own;
  ASSIGN_OR_RETURN(SourceLocator own_where, ParseTextMessage(text, path, &own));
  // Each file's own old-place fields move before it is laid over its base.
  RETURN_IF_ERROR(MoveSoccerPlannerFields(own_where, &own));
  if (!own.has_base_config()) {
    *run = std::move(own);
    *where = std::move(own_where);
    return absl::OkStatus();
  }
  chain->push_back(path);
  const std::string base_path = ResolvePath(DirName(path), own.base_config());
  const std::string at = own_where.Where({{"base_config"}});
  for (const std::string& seen : *chain) {
    if (CanonicalName(seen) == CanonicalName(base_path)) {
      return absl::InvalidArgumentError(absl::StrCat(
          at, ": a cycle of bases: ", absl::StrJoin(*chain, " -> "), " -> ", base_path));
    }
  }
  absl::StatusOr<std::string> base_text = ReadConfigFile(base_path);
  if (!base_text.ok()) {
    return absl::Status(base_text.status().code(),
                        absl::StrCat(at, ": ", base_text.status().message()));
  }
  config::RunConfig base;
  SourceLocator base_where("");
  RETURN_IF_ERROR(ParseComposed(*base_text, base_path, chain, &base, &base_where));
  chain->pop_back();
  // The base's file names keep naming its files from this file's folder.
  RebaseFileNames(DirName(base_path), DirName(path), &base);
  own.clear_base_config();
  MergeOver(own, &base);
  *run = std::move(base);
  *where = own_where.Over(base_where);
  return absl::OkStatus();
}

}  // namespace

absl::StatusOr<SourceLocator> ParseTextMessage(const std::string& text, const std::string& path,
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
  SourceLocator where(path, message->GetDescriptor(), std::move(tree));
  RETURN_IF_ERROR(CheckFieldRanges(*message, where));
  return where;
}

absl::StatusOr<std::string> ReadConfigFile(const std::string& path) {
  struct stat st;
  if (::stat(path.c_str(), &st) == 0 && S_ISDIR(st.st_mode)) {
    return absl::InvalidArgumentError(
        absl::StrCat(path, ": is a directory, not a config file (configs/*.textproto)"));
  }
  return ReadFile(path);
}

std::string ResolvePath(const std::string& dir, const std::string& relative) {
  if (relative.empty() || relative[0] == '/') return relative;
  return absl::StrCat(dir, "/", relative);
}

absl::StatusOr<LoadedConfig> ParseSharedRunConfig(const std::string& text,
                                                  const std::string& path) {
  LoadedConfig loaded;
  loaded.config_path = path;
  loaded.config_dir = DirName(path);
  std::vector<std::string> chain;
  RETURN_IF_ERROR(ParseComposed(text, path, &chain, &loaded.run, &loaded.root));
  const config::RunConfig& run = loaded.run;
  if (run.sampling().num_envs() < 1 || run.sampling().num_threads() < 1) {
    return absl::InvalidArgumentError(
        absl::StrCat(loaded.root.Where({{"sampling"}}), ": num_envs and num_threads must be >= 1"));
  }
  if (run.service().keep_checkpoints() < 1) {
    return absl::InvalidArgumentError(absl::StrCat(
        loaded.root.Nested({{"service"}}).Where({{"keep_checkpoints"}}), ": must be >= 1"));
  }
  const config::EvaluationConfig& eval = run.evaluation();
  const SourceLocator eval_where = loaded.root.Nested({{"evaluation"}});
  if (!(eval.every_minutes() >= 0) || eval.every_iterations() < 0) {
    return absl::InvalidArgumentError(
        absl::StrCat(eval_where.Where({{"every_minutes"}}), ": periods must be >= 0"));
  }
  if (eval.episodes() < 1 || eval.episodes() > 10000) {
    return absl::InvalidArgumentError(
        absl::StrCat(eval_where.Where({{"episodes"}}), ": must lie in [1, 10000]"));
  }
  if (!(eval.max_seconds() > 0 && eval.max_seconds() <= 3600)) {
    return absl::InvalidArgumentError(
        absl::StrCat(eval_where.Where({{"max_seconds"}}), ": must lie in (0, 3600]"));
  }
  return loaded;
}

}  // namespace juggle

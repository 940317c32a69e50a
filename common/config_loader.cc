#include "common/config_loader.h"

#include <fstream>
#include <sstream>

#include "absl/strings/str_cat.h"
#include "common/status_macros.h"
#include "common/toss_dims.h"
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

absl::Status ValidateToss(const config::TossConfig& t, const SourceLocator& where) {
  auto fail = [&](const char* field, const char* rule) {
    return absl::InvalidArgumentError(absl::StrCat(where.Where({{field}}), ": ", rule));
  };
  if (t.task() == config::TOSS_TASK_UNSPECIFIED) return fail("task", "must be CATCH or THROW");
  if (!(t.kp() > 0)) return fail("kp", "must be > 0");
  if (!(t.kd() >= 0)) return fail("kd", "must be >= 0");
  if (!(t.action_scale() > 0)) return fail("action_scale", "must be > 0");
  if (!(t.hand_period_s() > 0)) return fail("hand_period_s", "must be > 0");
  if (!(t.dwell_ratio() > 0 && t.dwell_ratio() < 1)) return fail("dwell_ratio", "must lie in (0, 1)");
  if (!(t.catch_radius() > 0)) return fail("catch_radius", "must be > 0");
  if (!(t.drop_z() < t.hand_z())) return fail("drop_z", "must be below hand_z");
  if (t.min_throw() < 1 || t.min_throw() == 2) return fail("min_throw", "must be 1 or >= 3");
  if (t.max_throw() < t.min_throw() || t.max_throw() > 9) {
    return fail("max_throw", "must lie in [min_throw, 9]");
  }
  if (!(t.landing_spread() >= 0)) return fail("landing_spread", "must be >= 0");
  if (!(t.flight_jitter() >= 0 && t.flight_jitter() < 0.5)) {
    return fail("flight_jitter", "must lie in [0, 0.5)");
  }
  if (!(t.catch_timing_jitter_s() >= 0 &&
        t.catch_timing_jitter_s() < t.dwell_ratio() * t.hand_period_s())) {
    return fail("catch_timing_jitter_s", "must lie in [0, dwell_ratio * hand_period_s)");
  }
  if (!(t.arrival_min_s() > 0 && t.arrival_max_s() >= t.arrival_min_s())) {
    return fail("arrival_max_s", "needs 0 < arrival_min_s <= arrival_max_s");
  }
  if (!(t.start_noise() >= 0)) return fail("start_noise", "must be >= 0");
  if (!(t.start_speed_noise() >= 0)) return fail("start_speed_noise", "must be >= 0");
  if (t.max_episode_steps() < 1) return fail("max_episode_steps", "must be >= 1");
  if (!(t.recorded_start_fraction() >= 0 && t.recorded_start_fraction() <= 1)) {
    return fail("recorded_start_fraction", "must lie in [0, 1]");
  }
  if (!(t.recorded_start_noise() >= 0)) return fail("recorded_start_noise", "must be >= 0");
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

namespace {

// Moves the states of `start_states_file` into `start_state` and checks every state's size.
absl::Status InlineStartStates(const std::string& config_dir, const SourceLocator& where,
                               config::TossConfig* toss) {
  if (toss->has_start_states_file()) {
    const std::string path = ResolvePath(config_dir, toss->start_states_file());
    absl::StatusOr<std::string> text = ReadFile(path);
    if (!text.ok()) {
      return absl::NotFoundError(
          absl::StrCat(where.Where({{"start_states_file"}}), ": ", text.status().message()));
    }
    config::TossArmStates states;
    absl::StatusOr<SourceLocator> parsed = ParseText(*text, path, &states);
    if (!parsed.ok()) return parsed.status();
    for (config::TossArmState& s : *states.mutable_state()) *toss->add_start_state() = std::move(s);
    toss->clear_start_states_file();
  }
  for (int i = 0; i < toss->start_state_size(); ++i) {
    const config::TossArmState& s = toss->start_state(i);
    if (s.angle_size() != kTossJoints || s.speed_size() != kTossJoints) {
      return absl::InvalidArgumentError(absl::StrCat(
          where.Where({{"start_state"}}), ": start state ", i, " has ", s.angle_size(),
          " angles and ", s.speed_size(), " speeds; each needs ", kTossJoints,
          " (neck, shoulder, elbow, wrist)"));
    }
  }
  return absl::OkStatus();
}

// Reads a binary ExportedPolicy file named by `field` into `policy`.
absl::Status InlinePolicyFile(const std::string& config_dir, const SourceLocator& where,
                              const char* field, const std::string& file,
                              config::ExportedPolicy* policy) {
  const std::string path = ResolvePath(config_dir, file);
  absl::StatusOr<std::string> bytes = ReadFile(path);
  if (!bytes.ok()) {
    return absl::NotFoundError(absl::StrCat(where.Where({{field}}), ": ", bytes.status().message(),
                                            " (write it with `juggle export-policy`)"));
  }
  if (!policy->ParseFromString(*bytes) || policy->parameters().empty()) {
    return absl::InvalidArgumentError(absl::StrCat(
        where.Where({{field}}), ": ", path,
        " is not an exported policy (write one with `juggle export-policy`)"));
  }
  return absl::OkStatus();
}

// In-loop training: both partner policies must be present (files are inlined). The patterns
// are checked against the model by TossSpec.
absl::Status PrepareLoop(const std::string& config_dir, const SourceLocator& toss_where,
                         config::TossConfig* toss) {
  if (!toss->has_loop()) return absl::OkStatus();
  const SourceLocator where = toss_where.Nested({{"loop"}});
  config::TossLoopConfig* loop = toss->mutable_loop();
  if (loop->pattern_size() == 0) {
    return absl::InvalidArgumentError(
        absl::StrCat(where.Where({{"pattern"}}), ": name at least one siteswap to juggle"));
  }
  if (loop->max_throws() < 1) {
    return absl::InvalidArgumentError(absl::StrCat(where.Where({{"max_throws"}}), ": must be >= 1"));
  }
  if (!(loop->start_noise() >= 0)) {
    return absl::InvalidArgumentError(absl::StrCat(where.Where({{"start_noise"}}), ": must be >= 0"));
  }
  if (loop->has_catch_policy_file()) {
    RETURN_IF_ERROR(InlinePolicyFile(config_dir, where, "catch_policy_file",
                                     loop->catch_policy_file(), loop->mutable_catch_policy()));
    loop->clear_catch_policy_file();
  }
  if (loop->has_throw_policy_file()) {
    RETURN_IF_ERROR(InlinePolicyFile(config_dir, where, "throw_policy_file",
                                     loop->throw_policy_file(), loop->mutable_throw_policy()));
    loop->clear_throw_policy_file();
  }
  if (!loop->has_catch_policy() || !loop->has_throw_policy()) {
    return absl::InvalidArgumentError(absl::StrCat(
        where.Where({{loop->has_catch_policy() ? "throw_policy_file" : "catch_policy_file"}}),
        ": the loop needs both partner policies (catch_policy_file and throw_policy_file)"));
  }
  return absl::OkStatus();
}

}  // namespace

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
  if (loaded.run.service().keep_checkpoints() < 1) {
    return absl::InvalidArgumentError(
        absl::StrCat(root.Nested({{"service"}}).Where({{"keep_checkpoints"}}), ": must be >= 1"));
  }

  if (loaded.run.has_toss()) {
    // Toss juggling has no control graph: an empty one keeps the walk and the wire format
    // uniform (zero edges, zero counts).
    loaded.env_locator = root.Nested({{"toss"}});
    if (loaded.run.has_graph() || loaded.run.has_graph_file()) {
      return absl::InvalidArgumentError(
          absl::StrCat(root.Where({{loaded.run.has_graph() ? "graph" : "graph_file"}}),
                       ": a toss config has no control graph"));
    }
    RETURN_IF_ERROR(ValidateToss(loaded.run.toss(), loaded.env_locator));
    RETURN_IF_ERROR(InlineStartStates(loaded.config_dir, loaded.env_locator,
                                      loaded.run.mutable_toss()));
    RETURN_IF_ERROR(PrepareLoop(loaded.config_dir, loaded.env_locator, loaded.run.mutable_toss()));
    loaded.graph = std::make_shared<const ControlGraph>();
    return loaded;
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

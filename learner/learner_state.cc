#include "learner/learner_state.h"

#include <sys/stat.h>

#include <cstring>


#include "absl/strings/numbers.h"
#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "absl/strings/str_split.h"
#include "envs/registry.h"

namespace juggle {

Sections SaveLearnerState(const StoredConfig& config, const std::string& config_path,
                          const PpoTrainer& trainer, const AdaptiveWalk& walk,
                          const RunProgress& progress) {
  Sections s = trainer.SaveState();
  s["run_config"] = config.text;
  s["model_mjb"] = config.model_mjb;
  s["config_path"] = config_path;
  const std::vector<double>& counts = walk.counts();
  s["edge_counts"] = std::string(reinterpret_cast<const char*>(counts.data()),
                                 counts.size() * sizeof(double));
  s["run_progress"] = absl::StrCat(progress.samples, " ", absl::StrFormat("%.3f", progress.train_seconds));
  return s;
}

absl::Status RestoreLearnerState(const Sections& sections, PpoTrainer* trainer,
                                 AdaptiveWalk* walk, RunProgress* progress) {
  auto it = sections.find("edge_counts");
  if (it == sections.end() || it->second.size() % sizeof(double) != 0) {
    return absl::DataLossError("checkpoint lacks valid edge counts");
  }
  std::vector<double> counts(it->second.size() / sizeof(double));
  std::memcpy(counts.data(), it->second.data(), it->second.size());
  // Check the counts against the graph before touching anything.
  AdaptiveWalk probe = *walk;
  if (absl::Status s = probe.SetCounts(counts); !s.ok()) {
    return absl::InvalidArgumentError(
        absl::StrCat("checkpoint edge counts do not fit this config's graph: ", s.message()));
  }
  RunProgress restored;
  if (auto p = sections.find("run_progress"); p != sections.end()) {
    const std::vector<std::string> fields = absl::StrSplit(p->second, ' ');
    if (fields.size() != 2 || !absl::SimpleAtoi(fields[0], &restored.samples) ||
        !absl::SimpleAtod(fields[1], &restored.train_seconds)) {
      return absl::DataLossError(absl::StrCat("checkpoint run_progress is unreadable: '",
                                              p->second, "'"));
    }
  }
  if (absl::Status s = trainer->RestoreState(sections); !s.ok()) return s;
  *walk = probe;
  if (progress != nullptr) *progress = restored;
  return absl::OkStatus();
}

absl::StatusOr<LoadedCheckpoint> LoadCheckpoint(const std::string& file_or_run_dir) {
  LoadedCheckpoint out;
  struct stat st;
  if (::stat(file_or_run_dir.c_str(), &st) != 0) {
    return absl::NotFoundError(absl::StrCat(file_or_run_dir, ": no such checkpoint or run directory"));
  }
  if (S_ISDIR(st.st_mode)) {
    absl::StatusOr<CheckpointDir::Loaded> loaded =
        CheckpointDir(file_or_run_dir + "/checkpoints").LoadLatest();
    if (!loaded.ok()) return loaded.status();
    out.path = loaded->path;
    out.sections = std::move(loaded->sections);
  } else {
    absl::StatusOr<Sections> sections = ReadCheckpointFile(file_or_run_dir);
    if (!sections.ok()) return sections.status();
    out.path = file_or_run_dir;
    out.sections = std::move(*sections);
  }
  if (out.sections.count("config_path")) out.config_path = out.sections["config_path"];
  const auto text = out.sections.find("run_config");
  const auto model = out.sections.find("model_mjb");
  if (text != out.sections.end() && model != out.sections.end()) {
    out.stored = StoredConfig{text->second, model->second};
  }
  return out;
}

absl::StatusOr<LoadedConfig> CheckpointConfig(const LoadedCheckpoint& checkpoint,
                                              std::string* note) {
  if (checkpoint.stored.has_value()) {
    absl::StatusOr<LoadedConfig> config = LoadStoredConfig(
        *checkpoint.stored, absl::StrCat(checkpoint.path, " (stored run config)"),
        checkpoint.config_path);
    if (!config.ok()) {
      return absl::Status(config.status().code(),
                          absl::StrCat(config.status().message(),
                                       " (pass --config to load the checkpoint under a config "
                                       "this build reads)"));
    }
    return config;
  }
  if (checkpoint.config_path.empty()) {
    return absl::FailedPreconditionError(
        absl::StrCat(checkpoint.path, " names no run config: pass --config"));
  }
  if (note != nullptr) {
    *note = absl::StrCat("note: ", checkpoint.path, " is an old-format checkpoint that names ",
                         checkpoint.config_path,
                         " by path: its config and model are read from there, as they are now");
  }
  return LoadRunConfig(checkpoint.config_path);
}

absl::StatusOr<config::ExportedPolicy> ExportPolicyFromCheckpoint(const Sections& sections,
                                                                  const LoadedConfig& config,
                                                                  int obs_dim, int act_dim) {
  PpoTrainer trainer(config.run.model(), config.run.ppo(), obs_dim, act_dim, 0);
  AdaptiveWalk walk(config.graph.get());
  if (absl::Status s = RestoreLearnerState(sections, &trainer, &walk, nullptr); !s.ok()) return s;
  config::ExportedPolicy exported;
  *exported.mutable_model() = config.run.model();
  exported.set_obs_dim(obs_dim);
  exported.set_act_dim(act_dim);
  exported.set_parameters(trainer.ExportPolicy().Serialize());
  return exported;
}

absl::StatusOr<EigenPolicy> PolicyFromCheckpoint(const Sections& sections,
                                                 const LoadedConfig& config, int obs_dim,
                                                 int act_dim) {
  absl::StatusOr<config::ExportedPolicy> exported =
      ExportPolicyFromCheckpoint(sections, config, obs_dim, act_dim);
  if (!exported.ok()) return exported.status();
  return PolicyFromExport(*exported);
}

}  // namespace juggle

#include "learner/learner_state.h"

#include <cstring>

#include "absl/strings/str_cat.h"
#include "google/protobuf/text_format.h"

namespace juggle {

Sections SaveLearnerState(const LoadedConfig& config, const PpoTrainer& trainer,
                          const AdaptiveWalk& walk) {
  Sections s = trainer.SaveState();
  std::string text;
  google::protobuf::TextFormat::PrintToString(config.run, &text);
  s["run_config"] = text;
  s["config_path"] = config.config_path;
  const std::vector<double>& counts = walk.counts();
  s["edge_counts"] = std::string(reinterpret_cast<const char*>(counts.data()),
                                 counts.size() * sizeof(double));
  return s;
}

absl::Status RestoreLearnerState(const Sections& sections, PpoTrainer* trainer,
                                 AdaptiveWalk* walk) {
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
  if (absl::Status s = trainer->RestoreState(sections); !s.ok()) return s;
  *walk = probe;
  return absl::OkStatus();
}

}  // namespace juggle

// One environment family: the RunConfig `family` case that selects it, the checks and file
// inlining of its section, and its EnvSpec factory. Implementations are stateless singletons
// (Thread-safe); envs/registry.cc lists them. Adding a family: docs/adding_an_env_family.md.
#ifndef JUGGLE_ENVS_ENV_FAMILY_H_
#define JUGGLE_ENVS_ENV_FAMILY_H_

#include <memory>
#include <string>
#include <string_view>

#include "absl/status/statusor.h"
#include "absl/strings/str_cat.h"
#include "common/config_loader.h"
#include "envs/env.h"
#include "proto/run_config.pb.h"

namespace juggle {

class EnvFamily {
 public:
  virtual ~EnvFamily() = default;
  // The oneof field's name, e.g. "soccer_juggle".
  virtual std::string_view name() const = 0;
  virtual config::RunConfig::FamilyCase config_case() const = 0;
  // Checks the family's section of `config->run` and inlines every file it names (so workers
  // receive one self-contained config); sets config->graph for families with a control graph.
  // Errors: INVALID_ARGUMENT / NOT_FOUND, each starting with "file:line:col: field".
  virtual absl::Status Prepare(LoadedConfig* config) const = 0;
  // Compiles the family's MJCF (or, given non-empty `model_mjb` or config.model_mjb, loads those
  // mj_saveModel bytes) and resolves everything against it. Errors name the config field or
  // the MJCF problem.
  // REQUIRES: `config` went through Prepare.
  virtual absl::StatusOr<std::shared_ptr<const EnvSpec>> CreateSpec(
      const LoadedConfig& config, const std::string& model_mjb) const = 0;
  // Makes `run` an evaluation config: episodes may last `max_seconds` of simulated time (0: the
  // config's limit) and training-only start curricula (soccer: random start phases) are off,
  // so every evaluation starts from the task's start distribution.
  // REQUIRES: `run` selects this family and was prepared; max_seconds >= 0.
  virtual void ConfigureForEvaluation(double max_seconds, config::RunConfig* run) const = 0;
  // Sets a constant world-frame force `force` (N, x y z) on the family's balls, for robustness
  // sweeps (paper Table 1; `juggle eval --force-sweep`). UNIMPLEMENTED, with the reason, for a
  // force with components the family cannot apply (the default: any force).
  // REQUIRES: `run` selects this family.
  virtual absl::Status SetConstantBallForce(const double force[3], config::RunConfig* run) const {
    return absl::UnimplementedError(
        absl::StrCat("the ", std::string(name()), " family has no constant force on its balls"));
  }
};

}  // namespace juggle

#endif  // JUGGLE_ENVS_ENV_FAMILY_H_

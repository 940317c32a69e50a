#include "common/env_family.h"

#include "common/juggle_dims.h"
#include "common/toss_dims.h"

namespace juggle {

EnvFamily EnvFamilyOf(const config::RunConfig& run) {
  return run.has_toss() ? EnvFamily::kToss : EnvFamily::kSoccer;
}

const char* EnvFamilyName(EnvFamily family) {
  return family == EnvFamily::kToss ? "toss" : "soccer";
}

EnvDims EnvDimsOf(const LoadedConfig& config) {
  switch (EnvFamilyOf(config.run)) {
    case EnvFamily::kToss:
      return {config.run.toss().task() == config::THROW ? kTossThrowObs : kTossCatchObs,
              kTossJoints, 1};
    case EnvFamily::kSoccer:
      break;
  }
  return {ObservationSize(config.graph->num_nodes()), kNumActions, config.graph->num_nodes()};
}

std::string ModelFilePath(const LoadedConfig& config) {
  const std::string& file = EnvFamilyOf(config.run) == EnvFamily::kToss
                                ? config.run.toss().model_file()
                                : config.run.env().model_file();
  return ResolvePath(config.config_dir, file);
}

double ControlDt(const LoadedConfig& config) {
  if (EnvFamilyOf(config.run) == EnvFamily::kToss) return 0.01;  // the model's timestep
  return config.run.env().sim_dt() * config.run.env().substeps();
}

}  // namespace juggle

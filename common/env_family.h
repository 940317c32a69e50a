// The one registry of environment families on the learner's side: which family a RunConfig
// selects and the sizes of its policy interface. Workers build the environments themselves
// (worker/env_registry.h); both switch on EnvFamilyOf, so adding a family means adding a case
// to these two files.
#ifndef JUGGLE_COMMON_ENV_FAMILY_H_
#define JUGGLE_COMMON_ENV_FAMILY_H_

#include <string>

#include "common/config_loader.h"

namespace juggle {

enum class EnvFamily {
  kSoccer,  // humanoid + ball on a control graph (seed 000): run.env + run.graph
  kToss,    // planar two-arm toss juggling (seed 001): run.toss
};

EnvFamily EnvFamilyOf(const config::RunConfig& run);
// "soccer" or "toss".
const char* EnvFamilyName(EnvFamily family);

struct EnvDims {
  int obs = 0;  // observation floats per env step
  int act = 0;  // action floats per env step
  int node_ids = 0;  // samples carry a node id in [0, node_ids): graph nodes; toss: 1 (the task)
};
EnvDims EnvDimsOf(const LoadedConfig& config);

// The family's MJCF file, resolved against the config's folder.
std::string ModelFilePath(const LoadedConfig& config);
// Seconds of simulated time per env step.
double ControlDt(const LoadedConfig& config);

}  // namespace juggle

#endif  // JUGGLE_COMMON_ENV_FAMILY_H_

// The football family (issue 45; docs/football.md): the juggling humanoid on a pitch with a
// size-5 ball, for PhysicsFC's skills (seed 002). RunConfig.football; spec, env, kick motion,
// passes, pitch physics and metrics live in this folder, in namespace juggle::football.
#ifndef JUGGLE_ENVS_FOOTBALL_FAMILY_H_
#define JUGGLE_ENVS_FOOTBALL_FAMILY_H_

#include "envs/env_family.h"

namespace juggle::football {

// The family's descriptor (a stateless singleton).
const EnvFamily& Family();

}  // namespace juggle::football

#endif  // JUGGLE_ENVS_FOOTBALL_FAMILY_H_

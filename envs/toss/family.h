// The toss-juggling family (Chemin & Lee, MIG 2018; docs/toss.md): a planar two-arm upper body juggles up to 7 balls by
// siteswap. RunConfig.toss; spec, tasks, in-loop env, runtime, siteswaps and the evaluation
// protocol live in this folder, in namespace juggle::toss.
#ifndef JUGGLE_ENVS_TOSS_FAMILY_H_
#define JUGGLE_ENVS_TOSS_FAMILY_H_

#include "envs/env_family.h"

namespace juggle::toss {

// The family's descriptor (a stateless singleton).
const EnvFamily& Family();

}  // namespace juggle::toss

#endif  // JUGGLE_ENVS_TOSS_FAMILY_H_

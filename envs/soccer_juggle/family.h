// The soccer-juggling family (Xie et al., SIGGRAPH 2022; docs/environment.md): a humanoid
// juggles a ball along a control graph. RunConfig.soccer_juggle; spec, env (with its base
// controller, start states and reward), reference poses and the graph cursor live in this
// folder, in namespace juggle::soccer_juggle.
#ifndef JUGGLE_ENVS_SOCCER_JUGGLE_FAMILY_H_
#define JUGGLE_ENVS_SOCCER_JUGGLE_FAMILY_H_

#include "envs/env_family.h"

namespace juggle::soccer_juggle {

// The family's descriptor (a stateless singleton).
const EnvFamily& Family();

}  // namespace juggle::soccer_juggle

#endif  // JUGGLE_ENVS_SOCCER_JUGGLE_FAMILY_H_

// When a MuJoCo simulation can no longer be trusted (issue 15: "a diverging simulation ends its
// episode and is counted"): the warnings that mean so, and non-finite positions or velocities.
// Shared by the humanoid families' envs (soccer juggling, football). Header-only.
#ifndef JUGGLE_ENVS_DIVERGENCE_H_
#define JUGGLE_ENVS_DIVERGENCE_H_

#include <cmath>

#include <mujoco/mujoco.h>

namespace juggle {

inline constexpr int kDivergenceWarnings[] = {mjWARN_BADQACC, mjWARN_BADQPOS, mjWARN_BADQVEL,
                                              mjWARN_CONTACTFULL, mjWARN_CNSTRFULL};

// Zeroes the counters of kDivergenceWarnings: call before each mj_step whose divergence
// SimulationDiverged then judges.
inline void ClearDivergenceWarnings(mjData* d) {
  for (int w : kDivergenceWarnings) d->warning[w].number = 0;
}

// True when one of kDivergenceWarnings was raised since the last clear, or a position or
// velocity is not finite.
inline bool SimulationDiverged(const mjModel* m, const mjData* d) {
  for (int w : kDivergenceWarnings) {
    if (d->warning[w].number > 0) return true;
  }
  for (int i = 0; i < m->nq; ++i) {
    if (!std::isfinite(d->qpos[i])) return true;
  }
  for (int i = 0; i < m->nv; ++i) {
    if (!std::isfinite(d->qvel[i])) return true;
  }
  return false;
}

}  // namespace juggle

#endif  // JUGGLE_ENVS_DIVERGENCE_H_

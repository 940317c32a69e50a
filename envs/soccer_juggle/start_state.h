// The start of a soccer-juggling episode (docs/environment.md, "Start states and juggles"): the
// character at the reference pose of its initial node, the ball on its reference path, both at
// rest, then varied by env.start (StartVariation; not in the release, which starts every
// episode from the same state — configs/right_foot_paper.textproto turns the variation off).
#ifndef JUGGLE_ENVS_SOCCER_JUGGLE_START_STATE_H_
#define JUGGLE_ENVS_SOCCER_JUGGLE_START_STATE_H_

#include <mujoco/mujoco.h>

#include "common/rng.h"
#include "envs/soccer_juggle/graph_cursor.h"
#include "envs/soccer_juggle/spec.h"

namespace juggle::soccer_juggle {

// Writes the start of an episode at `cursor`'s node into `data` (reset first, forwarded last)
// and the reference pose it starts at into `reference`. With probability
// env.start.random_phase_fraction a DOWN node starts at a phase drawn in [0, max_phase]
// (written to cursor->phase; the ball already falling from its apex); otherwise at the cursor's
// phase. Then env.start's noise moves the ball and the actuated joints. Every draw comes from
// `rng` in a fixed order: the same rng state gives the same start.
void PlaceAtStart(const JuggleSpec& spec, Rng* rng, CursorState* cursor, CharacterPose* reference,
                  mjData* data);

}  // namespace juggle::soccer_juggle

#endif  // JUGGLE_ENVS_SOCCER_JUGGLE_START_STATE_H_

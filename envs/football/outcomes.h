// How a football episode can end besides the shared outcomes (common/outcome.h).
#ifndef JUGGLE_ENVS_FOOTBALL_OUTCOMES_H_
#define JUGGLE_ENVS_FOOTBALL_OUTCOMES_H_

#include "common/outcome.h"

namespace juggle::football {

inline constexpr Outcome kFell = FamilyOutcome(0);        // root tilt or height beyond limits
inline constexpr Outcome kKicked = FamilyOutcome(1);      // settle_s after the kicking foot's touch
inline constexpr Outcome kWrongTouch = FamilyOutcome(2);  // another body touched the ball first
// TRAP: settle_s after the first touch by the designated part; the turf before any touch (a
// lob); another part first.
inline constexpr Outcome kTrapped = FamilyOutcome(3);
inline constexpr Outcome kGroundFirst = FamilyOutcome(4);
inline constexpr Outcome kWrongPart = FamilyOutcome(5);
// TRAP_KICK: the trapped ball did not come into the kick's zone within trap_kick.wait_s.
inline constexpr Outcome kOutOfReach = FamilyOutcome(6);

// Names of the family outcomes above, in value order.
inline constexpr const char* kOutcomeNames[] = {"fell",       "kicked",       "wrong_touch",
                                                "trapped",    "ground_first", "wrong_part",
                                                "out_of_reach"};

}  // namespace juggle::football

#endif  // JUGGLE_ENVS_FOOTBALL_OUTCOMES_H_

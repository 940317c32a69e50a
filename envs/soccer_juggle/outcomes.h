// How a soccer-juggling episode can end besides the shared outcomes (common/outcome.h).
#ifndef JUGGLE_ENVS_SOCCER_JUGGLE_OUTCOMES_H_
#define JUGGLE_ENVS_SOCCER_JUGGLE_OUTCOMES_H_

#include "common/outcome.h"

namespace juggle::soccer_juggle {

inline constexpr Outcome kFell = FamilyOutcome(0);            // root tilt or height beyond limits
inline constexpr Outcome kBallLost = FamilyOutcome(1);        // ball too low or too far from target
inline constexpr Outcome kBadContact = FamilyOutcome(2);      // ball touched a disallowed body
inline constexpr Outcome kContactTiming = FamilyOutcome(3);   // allowed contact outside the window
inline constexpr Outcome kAroundTheWorld = FamilyOutcome(4);  // foot–ball angle constraint violated
inline constexpr Outcome kStallLost = FamilyOutcome(5);       // ball left the stalling body

// Names of the family outcomes above, in value order.
inline constexpr const char* kOutcomeNames[] = {"fell",           "ball_lost",
                                                "bad_contact",    "contact_timing",
                                                "around_the_world", "stall_lost"};

}  // namespace juggle::soccer_juggle

#endif  // JUGGLE_ENVS_SOCCER_JUGGLE_OUTCOMES_H_

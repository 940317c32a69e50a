// How a toss-juggling episode can end besides the shared outcomes (common/outcome.h). Toss
// episodes end on these whether they succeed or not.
#ifndef JUGGLE_ENVS_TOSS_OUTCOMES_H_
#define JUGGLE_ENVS_TOSS_OUTCOMES_H_

#include "common/outcome.h"

namespace juggle::toss {

inline constexpr Outcome kCaught = FamilyOutcome(0);    // catch: the ball attached to the hand
inline constexpr Outcome kDropped = FamilyOutcome(1);   // catch: the ball fell or came too late
inline constexpr Outcome kReleased = FamilyOutcome(2);  // throw: the ball left at the release beat

// Names of the family outcomes above, in value order.
inline constexpr const char* kOutcomeNames[] = {"caught", "dropped", "released"};

}  // namespace juggle::toss

#endif  // JUGGLE_ENVS_TOSS_OUTCOMES_H_

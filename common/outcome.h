// Why an episode ended. Shared by workers (which end episodes) and the learner (which counts
// them by outcome on /metrics); the values travel on the wire as indices.
#ifndef JUGGLE_COMMON_OUTCOME_H_
#define JUGGLE_COMMON_OUTCOME_H_

#include <cstdint>

namespace juggle {

// Why an episode ended (kRunning while it has not).
enum class Outcome : uint8_t {
  kRunning = 0,
  kFell,            // root tilt or height beyond the limits
  kBallLost,        // ball too low or too far from its target
  kBadContact,      // ball touched a body not allowed in the node (or the floor)
  kContactTiming,   // ball touched an allowed body outside the contact window
  kAroundTheWorld,  // foot–ball angle constraint violated
  kStallLost,       // ball left the stalling body
  kDiverged,        // simulator warning or non-finite state
  kTimeLimit,       // truncated at max_episode_steps (not a failure)
  // Toss juggling (worker/toss_env.h): episodes end on these, success or not.
  kCaught,          // catch task: the ball attached to the hand (success)
  kDropped,         // catch task: the ball fell below the drop height
  kReleased,        // throw task: the ball left the hand at the release beat
  kNumOutcomes
};
// Stable snake_case name, e.g. "ball_lost"; "unknown" for values out of range.
const char* OutcomeName(Outcome o);

}  // namespace juggle

#endif  // JUGGLE_COMMON_OUTCOME_H_

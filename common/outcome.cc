#include "common/outcome.h"

namespace juggle {

const char* OutcomeName(Outcome o) {
  switch (o) {
    case Outcome::kRunning: return "running";
    case Outcome::kFell: return "fell";
    case Outcome::kBallLost: return "ball_lost";
    case Outcome::kBadContact: return "bad_contact";
    case Outcome::kContactTiming: return "contact_timing";
    case Outcome::kAroundTheWorld: return "around_the_world";
    case Outcome::kStallLost: return "stall_lost";
    case Outcome::kDiverged: return "diverged";
    case Outcome::kTimeLimit: return "time_limit";
    case Outcome::kCaught: return "caught";
    case Outcome::kDropped: return "dropped";
    case Outcome::kReleased: return "released";
    default: return "unknown";
  }
}

}  // namespace juggle

// JuggleSchedule: what each beat of a two-arm juggling run throws (envs/toss/juggler.h). A
// single pattern repeats forever; a transition run (`juggle toss --transitions=3,531,5,7,3`)
// juggles each pattern for a number of throws and passes between them by the shortest
// sequence of beats in the juggling-state graph (docs/siteswap.md). Between patterns of
// different ball counts a beat may also bring a ball into play (a hand with no ball due on
// that beat takes a new one before it and throws it) or take one out (the hand keeps the ball
// that lands on that beat and puts it away). Immutable value type; thread-safe.
#ifndef JUGGLE_ENVS_TOSS_JUGGLE_SCHEDULE_H_
#define JUGGLE_ENVS_TOSS_JUGGLE_SCHEDULE_H_

#include <string>
#include <vector>

#include "absl/status/statusor.h"
#include "envs/toss/siteswap.h"

namespace juggle::toss {

enum class BallChange { kNone, kAddBall, kRemoveBall };

struct ScheduledThrow {
  int value = 0;  // siteswap value; 0 for an empty beat or a ball taken out
  BallChange change = BallChange::kNone;
};

// The shortest beat sequence from `from` to `to` (states of width ≤ `width`, 1..16): a beat
// with a ball landing throws it (t ≥ 1 onto a free landing beat) or takes it out; a beat
// without one throws nothing or adds a ball (t ≥ 1). Among the shortest, the fewest ball
// changes. Equal states give an empty sequence. INVALID_ARGUMENT for bad widths or states.
absl::StatusOr<std::vector<ScheduledThrow>> FindScheduleTransition(JugglingState from,
                                                                   JugglingState to, int width);

class JuggleSchedule {
 public:
  // One pattern forever.
  explicit JuggleSchedule(const Siteswap& pattern);
  // Each pattern for at least `throws_each` beats (whole periods), the transitions between
  // them, and the last pattern forever after. INVALID_ARGUMENT for an empty list or a
  // transition that cannot be found.
  static absl::StatusOr<JuggleSchedule> Transitions(const std::vector<Siteswap>& patterns,
                                                    int throws_each);

  // This schedule up to `beat` (exclusive), then the shortest passage from the juggling state
  // its throws leave at `beat` into `next`, then `next` forever (the live page's pattern
  // choice). Beats before `beat` throw as before. INVALID_ARGUMENT for beat < 0, states wider
  // than 16 beats or no passage.
  absl::StatusOr<JuggleSchedule> SwitchAt(int beat, const Siteswap& next) const;
  // The juggling state at `beat`: bit k set when a ball thrown before `beat` lands at beat + k.
  JugglingState StateAt(int beat) const;

  // The throw of `beat`; beats < 0 repeat the first pattern (the run starts inside it).
  ScheduledThrow At(int beat) const;
  const Siteswap& first() const { return patterns_.front(); }
  // The largest value and the most balls in play anywhere in the schedule.
  int max_throw() const { return max_throw_; }
  int max_balls() const { return max_balls_; }
  // Beats before the last pattern starts (0 for a single pattern).
  int sequence_length() const { return static_cast<int>(sequence_.size()); }
  // "3>531>5" or the pattern.
  std::string Name() const;

 private:
  JuggleSchedule() = default;
  std::vector<Siteswap> patterns_;
  std::vector<ScheduledThrow> sequence_;  // beats 0.. before the last pattern repeats
  int max_throw_ = 0;
  int max_balls_ = 0;
};

}  // namespace juggle::toss

#endif  // JUGGLE_ENVS_TOSS_JUGGLE_SCHEDULE_H_

// Transition schedules (envs/toss/juggle_schedule.h): the transitions are checked by replaying
// them through the juggling-state rules independently of the search, and a transition run is
// juggled for real by the base controllers (envs/toss/base_controller.h).
#include <memory>

#include "gtest/gtest.h"
#include "envs/testing/test_configs.h"
#include "envs/toss/juggle_schedule.h"
#include "envs/toss/juggler.h"

namespace juggle::toss {
namespace {

// Replays `throws` from `state`; returns false on a throw the rules do not allow.
bool Replay(JugglingState state, const std::vector<ScheduledThrow>& throws, JugglingState* end,
            int* changes) {
  *changes = 0;
  for (const ScheduledThrow& t : throws) {
    const bool lands = state & 1;
    if (t.change == BallChange::kRemoveBall && (!lands || t.value != 0)) return false;
    if (t.change == BallChange::kAddBall && (lands || t.value == 0)) return false;
    if (t.change == BallChange::kNone && lands != (t.value > 0)) return false;
    if (t.change != BallChange::kNone) ++*changes;
    state >>= 1;
    if (t.value > 0) {
      const JugglingState bit = JugglingState{1} << (t.value - 1);
      if (state & bit) return false;  // two balls on one beat
      state |= bit;
    }
  }
  *end = state;
  return true;
}

Siteswap S(const char* text) { return *Siteswap::Parse(text); }

TEST(ScheduleTransitionTest, SameBallCountNeedsNoChangeAndIsAsShortAsTheSiteswapSearch) {
  for (auto [a, b] : {std::pair{"3", "531"}, std::pair{"531", "441"}, std::pair{"5", "744"}}) {
    const int width = std::max(S(a).max_throw(), S(b).max_throw());
    absl::StatusOr<std::vector<ScheduledThrow>> t =
        FindScheduleTransition(S(a).state(), S(b).state(), width);
    ASSERT_TRUE(t.ok()) << t.status();
    JugglingState end = 0;
    int changes = -1;
    ASSERT_TRUE(Replay(S(a).state(), *t, &end, &changes)) << a << " to " << b;
    EXPECT_EQ(end, S(b).state());
    EXPECT_EQ(changes, 0);
    EXPECT_EQ(t->size(), FindTransition(S(a).state(), S(b).state(), width)->throws.size());
  }
}

TEST(ScheduleTransitionTest, BallCountsChangeByAddingOrRemovingExactlyTheDifference) {
  for (auto [a, b, diff] : {std::tuple{"3", "5", 2}, std::tuple{"7", "3", 4},
                            std::tuple{"531", "7", 4}, std::tuple{"4", "53", 0}}) {
    absl::StatusOr<std::vector<ScheduledThrow>> t =
        FindScheduleTransition(S(a).state(), S(b).state(), 7);
    ASSERT_TRUE(t.ok()) << t.status();
    JugglingState end = 0;
    int changes = -1;
    ASSERT_TRUE(Replay(S(a).state(), *t, &end, &changes)) << a << " to " << b;
    EXPECT_EQ(end, S(b).state()) << a << " to " << b;
    EXPECT_EQ(changes, diff) << a << " to " << b;
  }
  EXPECT_FALSE(FindScheduleTransition(GroundState(3), GroundState(9), 7).ok());  // too wide
}

TEST(JuggleScheduleTest, RunsEachPatternThenTheTransitionThenTheLastPatternForever) {
  absl::StatusOr<JuggleSchedule> s = JuggleSchedule::Transitions({S("3"), S("531")}, 4);
  ASSERT_TRUE(s.ok()) << s.status();
  EXPECT_EQ(s->Name(), "3>531");
  EXPECT_EQ(s->At(-5).value, 3);  // before the run: the first pattern
  for (int beat = 0; beat < 4; ++beat) EXPECT_EQ(s->At(beat).value, 3);
  // 3 and 531 both start in "xxx": no transition beats are needed.
  EXPECT_EQ(s->sequence_length(), 4);
  EXPECT_EQ(s->At(4).value, 5);
  EXPECT_EQ(s->At(5).value, 3);
  EXPECT_EQ(s->At(6).value, 1);
  EXPECT_EQ(s->At(7 + 300).value, 5);
  EXPECT_EQ(s->max_balls(), 3);
  EXPECT_FALSE(JuggleSchedule::Transitions({}, 4).ok());
}

TEST(TransitionRunTest, BaseControllersJuggleThreeTo531To5To7AndBackToThreeWithoutADrop) {
  absl::StatusOr<LoadedConfig> config =
      LoadRunConfig(testing::RepoPath("configs/toss_base.textproto"));
  ASSERT_TRUE(config.ok()) << config.status();
  auto spec = TossSpec::Create(*config);
  ASSERT_TRUE(spec.ok()) << spec.status();
  absl::StatusOr<JuggleSchedule> schedule =
      JuggleSchedule::Transitions({S("3"), S("531"), S("5"), S("7"), S("3")}, 12);
  ASSERT_TRUE(schedule.ok()) << schedule.status();
  EXPECT_EQ(schedule->max_balls(), 7);
  JugglerOptions options;
  options.max_throws = schedule->sequence_length() + 12;
  options.seed = 5;
  auto juggler = TossJuggler::Create(*spec, *schedule, TossPolicies{}, options);
  ASSERT_TRUE(juggler.ok()) << juggler.status();
  const JuggleRunResult r = (*juggler)->Run();
  EXPECT_EQ(r.end, JuggleEnd::kMaxThrows) << JuggleEndName(r.end) << " after " << r.throws;
  int in_play = 0;
  for (int b = 0; b < kTossBalls; ++b) in_play += (*juggler)->world().mode(b) != BallMode::kParked;
  EXPECT_EQ(in_play, 3);  // back to three: four balls were put away
}

// The live page's pattern choice: beats before the switch throw as before, the passage from
// the state those throws leave is a legal juggle into the new pattern, which then repeats.
TEST(JuggleScheduleTest, SwitchAtKeepsTheBeatsBeforeAndPassesLegallyIntoTheNewPattern) {
  const JuggleSchedule three(S("3"));
  EXPECT_EQ(three.StateAt(7), S("3").state());
  for (const char* next : {"531", "5", "441", "3"}) {
    absl::StatusOr<JuggleSchedule> s = three.SwitchAt(7, S(next));
    ASSERT_TRUE(s.ok()) << next << ": " << s.status();
    for (int b = -3; b < 7; ++b) EXPECT_EQ(s->At(b).value, 3) << next << " beat " << b;
    std::vector<ScheduledThrow> passage;
    for (int b = 7; b < s->sequence_length(); ++b) passage.push_back(s->At(b));
    JugglingState end = 0;
    int changes = 0;
    ASSERT_TRUE(Replay(three.StateAt(7), passage, &end, &changes)) << next;
    EXPECT_EQ(end, S(next).state()) << next;
    EXPECT_EQ(s->StateAt(s->sequence_length()), S(next).state()) << next;
    for (int k = 0; k < 2 * S(next).period(); ++k) {
      EXPECT_EQ(s->At(s->sequence_length() + k).value, S(next).throws()[k % S(next).period()]);
    }
    EXPECT_EQ(s->Name(), std::string("3>") + next);
  }
  // A switch from inside the passage of a switch: the state at that beat, whatever it is.
  absl::StatusOr<JuggleSchedule> first = three.SwitchAt(4, S("531"));
  ASSERT_TRUE(first.ok());
  absl::StatusOr<JuggleSchedule> second = first->SwitchAt(first->sequence_length() + 1, S("5"));
  ASSERT_TRUE(second.ok()) << second.status();
  EXPECT_EQ(second->StateAt(second->sequence_length()), S("5").state());
  EXPECT_EQ(second->max_balls(), 5);
  EXPECT_FALSE(three.SwitchAt(-1, S("5")).ok());
}

}  // namespace
}  // namespace juggle::toss

// The two-arm runtime's sequencing (beat clock, catch/throw modes, handoffs, the initial ball
// placement) checked against the siteswap schedule itself: with arms resting at home and
// releases at exactly the schedule's velocity, every ball comes down into the right hand on
// time, so any pattern runs to the throw limit; with the palm's own (zero) velocity it cannot.
#include <algorithm>
#include <cmath>
#include <memory>
#include <vector>

#include "absl/strings/str_cat.h"
#include "gtest/gtest.h"
#include "envs/testing/test_configs.h"
#include "envs/toss/juggler.h"

namespace juggle::toss {
namespace {

std::shared_ptr<const TossSpec> CatchSpec() { return testing::LoadTossSpec("toss_catch"); }

JuggleRunResult RunPattern(const std::string& text, bool ideal, int max_throws,
                           TrajectoryBuilder* recording = nullptr) {
  absl::StatusOr<Siteswap> pattern = Siteswap::Parse(text);
  EXPECT_TRUE(pattern.ok()) << pattern.status();
  JugglerOptions options;
  options.max_throws = max_throws;
  options.start_noise = 0;
  options.ball_noise = 0;
  options.ball_speed_noise = 0;
  options.ideal_release = ideal;
  absl::StatusOr<std::unique_ptr<TossJuggler>> juggler =
      TossJuggler::Create(CatchSpec(), *pattern, TossPolicies{}, options);
  EXPECT_TRUE(juggler.ok()) << juggler.status();
  return (*juggler)->Run(recording);
}

class IdealReleaseTest : public ::testing::TestWithParam<const char*> {};

TEST_P(IdealReleaseTest, ScheduledThrowsIntoRestingHandsRunToTheThrowLimit) {
  const JuggleRunResult r = RunPattern(GetParam(), /*ideal=*/true, 60);
  EXPECT_EQ(r.end, JuggleEnd::kMaxThrows) << GetParam() << " ended " << JuggleEndName(r.end)
                                          << " after " << r.throws << " throws";
  EXPECT_EQ(r.throws, 60);
  // Beat −1 is at t = 0 (thrown before the run); the 60th throw is beat 59, at 60 · 0.25 s.
  EXPECT_NEAR(r.seconds, 60 * 0.25, 0.011);
}

// Both hands rest at home, so every recorded state is the home pose in the right arm's frame
// (the left hand's states mirrored back): one catch start per release, one throw start per catch.
TEST(TossJugglerTest, RecordsTheArmStateInTheRightArmsFrameAtEveryReleaseAndCatch) {
  const JuggleRunResult r = RunPattern("3", /*ideal=*/true, 20);
  ASSERT_EQ(r.throws, 20);
  EXPECT_EQ(r.catch_starts.size(), 20u);
  EXPECT_EQ(r.throw_starts.size(), static_cast<size_t>(r.catches));
  EXPECT_GE(r.catches, 17);  // all but the balls still in the air at the 20th throw
  const std::array<double, kTossJoints> home = CatchSpec()->home();
  for (const auto* starts : {&r.catch_starts, &r.throw_starts}) {
    for (const TossArmState& s : *starts) {
      for (int j = 1; j < kTossJoints; ++j) {
        EXPECT_NEAR(s.angle[j], home[j], 0.05) << "joint " << j;
        EXPECT_NEAR(s.speed[j], 0, 1.0) << "joint " << j;
      }
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Patterns, IdealReleaseTest,
                         ::testing::Values("3", "4", "5", "53", "441", "531", "6", "7"),
                         [](const auto& info) { return std::string("pattern_") + info.param; });

TEST(TossJugglerTest, HandoffOfAOneMovesTheBallToTheOtherHandWithoutAFlight) {
  // 441 with ideal releases: every third throw is a handoff, so catches are 2 per 3 throws.
  const JuggleRunResult r = RunPattern("441", true, 30);
  ASSERT_EQ(r.end, JuggleEnd::kMaxThrows);
  EXPECT_NEAR(r.catches, 30 * 2 / 3, 2);
}

TEST(TossJugglerTest, HandWaitsForABallPassedToItBeforeChasingTheNextFreeOne) {
  // 531: beat 0 (R) 5, beat 1 (L) 3, beat 2 (R) 1 — a handoff to L at 0.75 s — beat 3 (L) 5.
  JugglerOptions options;
  options.start_noise = 0;
  options.ball_noise = 0;
  options.ball_speed_noise = 0;
  options.ideal_release = true;
  absl::StatusOr<std::unique_ptr<TossJuggler>> made =
      TossJuggler::Create(CatchSpec(), *Siteswap::Parse("531"), TossPolicies{}, options);
  ASSERT_TRUE(made.ok()) << made.status();
  TossJuggler& j = **made;
  auto step_to = [&](double t) {
    while (j.world().time() < t - 1e-9) ASSERT_TRUE(j.Step());
  };
  step_to(0.6);  // L threw its 3 at 0.5 s; R holds the ball it passes at 0.75 s
  ASSERT_LT(j.world().held_by(Hand::kLeft), 0);
  ASSERT_GE(j.world().held_by(Hand::kRight), 0);
  EXPECT_EQ(j.IncomingBall(Hand::kLeft), -1) << "the 5 thrown at beat 0 is due later";
  step_to(0.8);
  EXPECT_GE(j.world().held_by(Hand::kLeft), 0) << "handed over at 0.75 s";
  step_to(1.05);  // L threw the 5 at 1.0 s; R's next throw (beat 4) is a 3, not a handoff
  ASSERT_LT(j.world().held_by(Hand::kLeft), 0);
  EXPECT_GE(j.IncomingBall(Hand::kLeft), 0) << "now L chases beat 0's 5";
  EXPECT_FALSE(j.HoldsThrow(Hand::kLeft));
}

TEST(TossJugglerTest, ThreeStartsWithOneBallInTheFirstThrowersHandAndTwoInTheAir) {
  TrajectoryBuilder recording = TossJuggler::NewRecording(*CatchSpec(), 3, "c");
  RunPattern("3", true, 3, &recording);
  const Trajectory& t = recording.trajectory();
  ASSERT_GT(t.num_samples(), 0);
  ASSERT_GE(t.FindChannel("ball2_mode"), 0);
  EXPECT_LT(t.FindChannel("ball3_mode"), 0);  // three balls recorded
  int held = 0, free = 0;
  for (int b = 0; b < 3; ++b) {
    const std::string mode = t.Label(0, t.FindChannel(absl::StrCat("ball", b, "_mode")));
    held += mode == "held";
    free += mode == "free";
    if (mode != "held") continue;
    // In the right palm.
    EXPECT_NEAR(t.value(0, t.FindChannel(absl::StrCat("ball", b, "_x"))),
                t.value(0, t.FindChannel("right_palm_x")), 1e-9);
    EXPECT_NEAR(t.value(0, t.FindChannel(absl::StrCat("ball", b, "_z"))),
                t.value(0, t.FindChannel("right_palm_z")), 1e-9);
  }
  EXPECT_EQ(held, 1);  // the right hand's, for beat 0
  EXPECT_EQ(free, 2);  // thrown on beats −2 and −1 (the latter just released, at the left palm)
  // The run ends at the throw limit, recorded as its outcome.
  EXPECT_EQ(t.Label(t.num_samples() - 1, kOutcomeChannel), "max_throws");
}

TEST(TossJugglerTest, ReleasingWithTheRestingPalmsVelocityBreaksThePatternAtOnce) {
  const JuggleRunResult r = RunPattern("3", /*ideal=*/false, 60);
  EXPECT_NE(r.end, JuggleEnd::kMaxThrows);
  EXPECT_LT(r.throws, 5);
  EXPECT_GT(r.mean_velocity_error, 1.5);  // the 3's target is (±1.0, 1.96) m/s
}

TEST(TossJugglerTest, MoreBallsThanTheModelHoldsIsAnError) {
  absl::StatusOr<std::unique_ptr<TossJuggler>> juggler =
      TossJuggler::Create(CatchSpec(), *Siteswap::Parse("9"), TossPolicies{}, JugglerOptions{});
  ASSERT_FALSE(juggler.ok());
  EXPECT_EQ(juggler.status().code(), absl::StatusCode::kInvalidArgument);
}

}  // namespace
}  // namespace juggle::toss

namespace juggle::toss {
namespace {

// The start perturbation (JugglerOptions: ± 0.05 rad, balls ± 2 cm and ± 0.1 m/s) is the same
// for one seed and differs between seeds, by much more than the 0.002 rad before issue 28.
TEST(TossJugglerStartTest, StartVariationIsDeterministicPerSeedAndDiffersBetweenSeeds) {
  auto start = [](uint64_t seed) {
    JugglerOptions options;
    options.seed = seed;
    auto juggler = TossJuggler::Create(CatchSpec(), *Siteswap::Parse("5"), TossPolicies{}, options);
    EXPECT_TRUE(juggler.ok()) << juggler.status();
    const mjData* d = (*juggler)->world().data();
    const int n = (*juggler)->world().spec().model()->nq + (*juggler)->world().spec().model()->nv;
    std::vector<double> state(d->qpos, d->qpos + (*juggler)->world().spec().model()->nq);
    state.insert(state.end(), d->qvel, d->qvel + (n - state.size()));
    return state;
  };
  EXPECT_EQ(start(1001), start(1001));
  const std::vector<double> a = start(1001), b = start(1002);
  double largest = 0;
  for (size_t i = 0; i < a.size(); ++i) largest = std::max(largest, std::abs(a[i] - b[i]));
  EXPECT_GT(largest, 0.1);  // speeds ± 0.5 rad/s; with ± 0.002 rad (± 0.02 rad/s) it would fail
}

}  // namespace
}  // namespace juggle::toss

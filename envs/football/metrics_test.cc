// The trap and kick metrics (envs/football/metrics.h) on hand-made attempts whose values are
// known: a kick 5° off at 12 m/s against 10 gives KDD 5° and KSD 2 m/s; a kick along its target
// under gravity gives the angles the law of cosines gives; the signed errors' sides and signs;
// traps by each rule.
#include "envs/football/metrics.h"

#include <algorithm>
#include <cmath>

#include "gmock/gmock.h"
#include "gtest/gtest.h"

namespace juggle::football {
namespace {

// Samples at 50 Hz from the touch to 0.3 s of a constant velocity v, or of v under gravity.
KickAttempt KickWith(const double v[3], const double target[3], double target_speed,
                     double gravity) {
  KickAttempt k;
  k.touched = true;
  for (int i = 0; i < 3; ++i) k.target_direction[i] = target[i];
  k.target_speed = target_speed;
  for (int i = 0; i <= 15; ++i) {
    BallVelocitySample s;
    s.t = 0.02 * i;
    for (int j = 0; j < 3; ++j) s.velocity[j] = v[j];
    s.velocity[2] -= gravity * s.t;
    k.after_touch.push_back(s);
  }
  return k;
}

TEST(KickMetricsTest, AKickFiveDegreesOffAtTwelveAgainstTenGivesFiveDegreesAndTwoMetres) {
  const double angle = 5 * M_PI / 180;
  const double v[3] = {12 * std::cos(angle), 12 * std::sin(angle), 0};
  const double target[3] = {3, 0, 0};  // not unit length: only its direction counts
  const KickScore s = ScoreKick(KickWith(v, target, 10, 0));
  ASSERT_TRUE(s.success);
  EXPECT_EQ(s.samples, 9) << "t = 0, 0.02, ..., 0.16 lie within 1/6 s";
  EXPECT_NEAR(s.direction_deviation_deg, 5.0, 1e-9);
  EXPECT_NEAR(s.speed_deviation_mps, 2.0, 1e-12);
}

TEST(KickMetricsTest, AKickAlongItsTargetUnderGravityDeviatesAsTheLawOfCosinesSays) {
  // Launched exactly along the target (20° up, at the target speed): at time t the velocity is
  // v0 − g·t·ẑ; the angle to v0 by the law of cosines on |v0|, |v(t)| and g·t.
  const double g = 9.81, speed = 15, up = 20 * M_PI / 180;
  const double v0[3] = {speed * std::cos(up), 0, speed * std::sin(up)};
  const KickScore s = ScoreKick(KickWith(v0, v0, speed, g));
  double angles = 0, speeds = 0;
  int n = 0;
  for (int i = 0; 0.02 * i <= 1.0 / 6.0; ++i, ++n) {
    const double t = 0.02 * i;
    const double vt = std::hypot(v0[0], v0[2] - g * t);
    const double c = (speed * speed + vt * vt - g * t * g * t) / (2 * speed * vt);
    angles += std::acos(std::min(1.0, c)) * 180 / M_PI;
    speeds += std::abs(vt - speed);
  }
  ASSERT_TRUE(s.success);
  EXPECT_EQ(s.samples, n);
  EXPECT_NEAR(s.direction_deviation_deg, angles / n, 1e-6);
  EXPECT_NEAR(s.speed_deviation_mps, speeds / n, 1e-9);
  EXPECT_GT(s.direction_deviation_deg, 1.0) << "gravity bends a 15 m/s kick by degrees in 1/6 s";
}

TEST(KickMetricsTest, SignedErrorsGiveTheSideAndTheSignOfTheDeviations) {
  // 5° to the left (toward +y) and 3° below a target 10° up, 2 m/s slow: each error with its sign.
  const double left = 5 * M_PI / 180, down = 7 * M_PI / 180, up = 10 * M_PI / 180;
  const double v[3] = {8 * std::cos(down) * std::cos(left), 8 * std::cos(down) * std::sin(left),
                       8 * std::sin(down)};
  const double target[3] = {std::cos(up), 0, std::sin(up)};
  const KickErrors e = SignedKickErrors(KickWith(v, target, 10, 0));
  ASSERT_TRUE(e.valid);
  EXPECT_NEAR(e.azimuth_deg, 5.0, 1e-9);
  EXPECT_NEAR(e.elevation_deg, -3.0, 1e-9);
  EXPECT_NEAR(e.speed_mps, -2.0, 1e-12);
  // Toward −y behind the target's azimuth of 175°: wrapped, −10° rather than 350°.
  const double back[3] = {std::cos(175 * M_PI / 180), std::sin(175 * M_PI / 180), 0};
  const double turned[3] = {-std::cos(5 * M_PI / 180), -std::sin(5 * M_PI / 180), 0};
  EXPECT_NEAR(SignedKickErrors(KickWith(turned, back, 1, 0)).azimuth_deg, 10.0, 1e-9);
}

TEST(KickMetricsTest, UnderGravityTheMeanElevationErrorIsHalfTheTurnAndKddNoLessThanAQuarter) {
  // Launched along its target at 15 m/s, 20° up: the elevation error falls from 0 with each
  // sample's own angle (atan2 of the velocity, an independent path to the law of cosines above),
  // and no aim does better than a quarter of the window's turn in KDD.
  const double g = 9.81, speed = 15, up = 20 * M_PI / 180;
  const double v0[3] = {speed * std::cos(up), 0, speed * std::sin(up)};
  const KickAttempt k = KickWith(v0, v0, speed, g);
  double sum = 0;
  int n = 0;
  for (int i = 0; 0.02 * i <= 1.0 / 6.0; ++i, ++n) {
    sum += std::atan2(v0[2] - g * 0.02 * i, v0[0]) - up;
  }
  const KickErrors e = SignedKickErrors(k);
  ASSERT_TRUE(e.valid);
  EXPECT_NEAR(e.elevation_deg, sum / n * 180 / M_PI, 1e-9);
  EXPECT_LT(e.elevation_deg, 0);
  EXPECT_NEAR(e.azimuth_deg, 0, 1e-12);
  const double turn_deg = (std::atan2(v0[2] - g * 0.16, v0[0]) - up) * -180 / M_PI;
  EXPECT_NEAR(e.elevation_deg, -turn_deg / 2, 0.05 * turn_deg);
  EXPECT_GE(ScoreKick(k).direction_deviation_deg, turn_deg / 4);
  KickAttempt untouched = k;
  untouched.touched = false;
  EXPECT_FALSE(SignedKickErrors(untouched).valid);
}

TEST(KickMetricsTest, TheFloorIsWhatNoAimBeatsUnderGravityAndZeroForAStraightFlight) {
  const double g = 9.81, speed = 10, up = 15 * M_PI / 180;
  const double v0[3] = {speed * std::cos(up), 0, speed * std::sin(up)};
  const KickAttempt k = KickWith(v0, v0, speed, g);
  const KickFloor floor = KickDeviationFloor(k);
  // Against a grid of targets in the flight's plane and beside it, none gives less KDD.
  double best = 1e9;
  for (double el = 0; el <= 20; el += 0.05) {
    for (double az : {-0.5, 0.0, 0.5}) {
      KickAttempt aimed = k;
      const double e = el * M_PI / 180, a = az * M_PI / 180;
      aimed.target_direction[0] = std::cos(e) * std::cos(a);
      aimed.target_direction[1] = std::cos(e) * std::sin(a);
      aimed.target_direction[2] = std::sin(e);
      best = std::min(best, ScoreKick(aimed).direction_deviation_deg);
    }
  }
  EXPECT_GT(floor.direction_deg, 1.0) << "a 10 m/s kick turns by about 9 degrees in 1/6 s";
  EXPECT_LE(floor.direction_deg, best + 1e-9);
  EXPECT_NEAR(floor.direction_deg, best, 0.01);
  EXPECT_GT(floor.speed_mps, 0);
  const double flat[3] = {12, 1, 0};
  const KickFloor straight = KickDeviationFloor(KickWith(flat, v0, 20, 0));
  EXPECT_NEAR(straight.direction_deg, 0, 1e-9);
  EXPECT_NEAR(straight.speed_mps, 0, 1e-12);
}

TEST(KickMetricsTest, AnUntouchedKickFailsAndAKickWithoutSamplesInTheWindowIsNotMeasured) {
  const double v[3] = {10, 0, 0};
  KickAttempt missed = KickWith(v, v, 10, 0);
  missed.touched = false;
  EXPECT_FALSE(ScoreKick(missed).success);
  KickAttempt late = KickWith(v, v, 10, 0);
  for (BallVelocitySample& s : late.after_touch) s.t += 1.0;
  EXPECT_FALSE(ScoreKick(late).success);
}

TEST(TrapMetricsTest, SuccessNeedsTheDesignatedPartFirstAndTheBallWithinReach) {
  TrapAttempt t;
  t.designated_first_before_ground = true;
  t.within_reach_after = true;
  t.relative_speed_after_touch = {1, 2, 3, 4, 5, 99};
  TrapScore s = ScoreTrap(t);
  EXPECT_TRUE(s.success);
  EXPECT_FALSE(s.handball);
  ASSERT_TRUE(s.measured_speed);
  EXPECT_DOUBLE_EQ(s.relative_speed, 3.0) << "the first 5 frames only";
  t.within_reach_after = false;
  EXPECT_FALSE(ScoreTrap(t).success) << "the ball got away";
  t.within_reach_after = true;
  t.designated_first_before_ground = false;
  EXPECT_FALSE(ScoreTrap(t).success) << "another part first, or the ground first";
  t.designated_first_before_ground = true;
  t.arms_touched = true;
  s = ScoreTrap(t);
  EXPECT_TRUE(s.success && s.handball);
  t.relative_speed_after_touch = {1, 2};
  EXPECT_FALSE(ScoreTrap(t).measured_speed) << "fewer than 5 frames";
}

TEST(FootballMetricsTest, TheSummaryLineAggregatesAsPhysicsFcDefinesEachRate) {
  FootballMetrics m;
  EXPECT_THAT(m.SummaryLine(), ::testing::HasSubstr("tsr=nan"));
  // 4 traps: 3 successes (one a handball, one without a speed measurement), 1 failure.
  TrapScore ok{true, false, 2.0, true}, hand{true, true, 4.0, true}, unmeasured{true, false, 0, false},
      failed{false, false, 9.0, true};
  for (const TrapScore& t : {ok, hand, unmeasured, failed}) m.Add(t);
  // 2 kicks: one scored 4° / 1 m/s, one missed.
  m.Add(KickScore{true, 4.0, 1.0, 9});
  m.Add(KickScore{});
  m.AddTrapThenKick(true);
  m.AddTrapThenKick(true);
  m.AddTrapThenKick(false);
  m.AddTrapThenKick(true);
  EXPECT_DOUBLE_EQ(m.tsr(), 0.75);
  EXPECT_DOUBLE_EQ(m.hrts(), 1.0 / 3);
  EXPECT_DOUBLE_EQ(m.rbspt_mps(), 3.0) << "over the measured successes only";
  EXPECT_DOUBLE_EQ(m.ksr(), 0.5);
  EXPECT_DOUBLE_EQ(m.kdd_deg(), 4.0);
  EXPECT_DOUBLE_EQ(m.ksd_mps(), 1.0);
  EXPECT_DOUBLE_EQ(m.trap_kick(), 0.75);
  EXPECT_EQ(m.SummaryLine(),
            "tsr=0.750 hrts=0.333 rbspt_mps=3.000 ksr=0.500 kdd_deg=4.000 ksd_mps=1.000 "
            "trap_kick=0.750");
}

}  // namespace
}  // namespace juggle::football

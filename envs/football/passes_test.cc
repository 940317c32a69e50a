// Passes (envs/football/passes.h) flown and rolled in the pitch model: a lob lands where it was
// asked within the Euler integrator's known error, a ground pass arrives at its speed, sampling
// is deterministic and keeps its ranges, bad ranges are refused by name.
#include "envs/football/passes.h"

#include <cmath>
#include <vector>

#include "envs/football/pitch.h"
#include "envs/football/testing/pitch_fixture.h"
#include "gmock/gmock.h"

namespace juggle::football {
namespace {

using ::testing::HasSubstr;

constexpr double kOffsetY = 30;  // passes flown beside the character, out of its reach

class PassFlightTest : public testing::PitchFixture {
 protected:
  // Starts `p` shifted by kOffsetY, the ball rolling without slipping if on the turf.
  void Launch(const Pass& p) {
    PlaceBall(p.start[0], p.start[1] + kOffsetY, p.start[2]);
    if (p.kind == PassKind::kGround) {
      Roll(p.velocity[0], p.velocity[1]);
    } else {
      for (int i = 0; i < 3; ++i) ball_vel()[i] = p.velocity[i];
    }
    mj_forward(m_, d_);
  }
};

TEST_F(PassFlightTest, ALobLandsWhereItWasAskedWithinTheEulerIntegratorsError) {
  struct Case {
    double landing[2], heading_deg, speed, angle_deg;
  };
  for (const Case& c : {Case{{0.5, 0.0}, 180, 10, 45}, Case{{0.8, -0.3}, 200, 14, 30},
                        Case{{0.3, 0.2}, 150, 8, 60}, Case{{0.6, 0.1}, 170, 12, 55}}) {
    SCOPED_TRACE(c.heading_deg);
    const Pass p = LobPassLandingAt(c.landing, c.heading_deg * M_PI / 180, c.speed, c.angle_deg,
                                    0.13, radius_, g_);
    Launch(p);
    // Step until the centre comes down through the ball-radius height; interpolate.
    double before[3], after[3];
    double t = 0;
    bool landed = false;
    for (int i = 0; i < 4000 && !landed; ++i) {
      for (int k = 0; k < 3; ++k) before[k] = ball_pos()[k];
      mj_step(m_, d_);
      t += m_->opt.timestep;
      for (int k = 0; k < 3; ++k) after[k] = ball_pos()[k];
      landed = ball_vel()[2] < 0 && after[2] <= radius_;
    }
    ASSERT_TRUE(landed);
    const double f = (before[2] - radius_) / (before[2] - after[2]);
    const double x = before[0] + f * (after[0] - before[0]);
    const double y = before[1] + f * (after[1] - before[1]) - kOffsetY;
    const double miss = std::hypot(x - p.target[0], y - p.target[1]);
    // Semi-implicit Euler flies g·dt·t/2 low at time t: it lands early by that drop over the
    // vertical speed, short by the horizontal speed times that.
    const double vz_landing = p.velocity[2] - g_ * p.arrival_s;
    const double drop = g_ * m_->opt.timestep * p.arrival_s / 2;
    const double bound = std::hypot(p.velocity[0], p.velocity[1]) * drop / std::abs(vz_landing);
    // Measured: the miss is Euler's to 10 µm (1-3 cm at these flights).
    EXPECT_NEAR(miss, bound, 1e-3) << "landed " << miss << " m away; Euler predicts " << bound;
    EXPECT_NEAR(t, p.arrival_s, 2 * m_->opt.timestep + drop / std::abs(vz_landing));
  }
}

TEST_F(PassFlightTest, AGroundPassReachesItsAimPointAtItsSpeed) {
  const double deceleration = RollingDeceleration(m_, ball_);
  for (double arrival : {2.0, 4.0, 6.0}) {
    SCOPED_TRACE(arrival);
    const double aim[2] = {0.4, 0};
    const Pass p = GroundPassArrivingAt(aim, M_PI, arrival, 12, deceleration, radius_);
    EXPECT_NEAR(p.start[0], 12.4, 1e-12);
    Launch(p);
    double speed = 0;
    for (int i = 0; i < 40000 && ball_pos()[0] > aim[0]; ++i) mj_step(m_, d_);
    speed = std::hypot(ball_vel()[0], ball_vel()[1]);
    // The deceleration that speed implies over the 12 m: the formula's, less what the first
    // second of a roll loses while MuJoCo's soft friction builds its slip (docs/football.md:
    // 0.79 instead of 0.90 m/s² then): within 8 %.
    const double v0 = std::hypot(p.velocity[0], p.velocity[1]);
    const double implied = (v0 * v0 - speed * speed) / (2 * 12);
    EXPECT_NEAR(implied / deceleration, 1.0, 0.08) << "arrived at " << speed << " m/s";
    EXPECT_NEAR(speed, arrival, 0.25);
    EXPECT_NEAR(ball_pos()[1] - kOffsetY, 0, 1e-3);
  }
}

TEST(PassSamplingTest, SamplingIsDeterministicAndKeepsItsRangesAndTheLobShare) {
  const PassRanges r;
  ASSERT_TRUE(ValidatePassRanges(r).ok());
  Rng a(Rng::ForStream(3, 0, 1)), b(Rng::ForStream(3, 0, 1));
  int lobs = 0;
  constexpr int kPasses = 2000;
  for (int i = 0; i < kPasses; ++i) {
    const Pass p = SamplePass(r, 0.11, 9.81, 0.9, a);
    const Pass q = SamplePass(r, 0.11, 9.81, 0.9, b);
    ASSERT_EQ(p.start[0], q.start[0]);
    ASSERT_EQ(p.velocity[2], q.velocity[2]);
    if (p.kind == PassKind::kLob) {
      ++lobs;
      const double distance = std::hypot(p.target[0], p.target[1]);
      EXPECT_GE(distance, r.landing_distance_min - 1e-9);
      EXPECT_LE(distance, r.landing_distance_max + 1e-9);
      EXPECT_LE(std::abs(std::atan2(p.target[1], p.target[0])),
                r.landing_bearing_max_deg * M_PI / 180 + 1e-9);
      EXPECT_GT(p.start[0], p.target[0]) << "lobs come from in front";
      EXPECT_LT(p.velocity[0], 0);
      const double speed = std::hypot(p.velocity[0], p.velocity[1], p.velocity[2]);
      EXPECT_GE(speed, r.launch_speed_min - 1e-9);
      EXPECT_LE(speed, r.launch_speed_max + 1e-9);
      EXPECT_NEAR(p.start[2], r.launch_height, 1e-12);
    } else {
      EXPECT_NEAR(std::hypot(p.start[0] - p.target[0], p.start[1] - p.target[1]),
                  r.ground_start_distance, 1e-9);
      EXPECT_GE(p.arrival_speed, r.ground_arrival_speed_min);
      EXPECT_LE(p.arrival_speed, r.ground_arrival_speed_max);
    }
  }
  EXPECT_NEAR(double(lobs) / kPasses, r.lob_fraction, 0.03);
}

TEST(PassSamplingTest, BadRangesAreRefusedNamingTheField) {
  PassRanges r;
  r.launch_angle_min_deg = 70;  // above the max
  EXPECT_THAT(std::string(ValidatePassRanges(r).message()), HasSubstr("launch_angle_min_deg"));
  r = PassRanges();
  r.lob_fraction = 1.5;
  EXPECT_THAT(std::string(ValidatePassRanges(r).message()), HasSubstr("lob_fraction"));
  r = PassRanges();
  r.launch_speed_max = 100;
  EXPECT_THAT(std::string(ValidatePassRanges(r).message()), HasSubstr("launch_speed_max"));
  r = PassRanges();
  r.launch_height = 0;
  EXPECT_THAT(std::string(ValidatePassRanges(r).message()), HasSubstr("launch_height"));
}

TEST(PassThroughTest, ALobComesDownThroughItsPointAndAdvancingMovesAlongTheFlight) {
  const double g = 9.81, r = 0.11;
  const double point[3] = {0.4, -0.1, 1.3};
  absl::StatusOr<Pass> p = LobPassThrough(point, M_PI + 0.2, 12, 50, 0.13, r, g);
  ASSERT_TRUE(p.ok()) << p.status();
  // The analytic flight at meet_s is at the point, coming down, before the landing.
  const double t = p->meet_s;
  EXPECT_NEAR(p->start[0] + p->velocity[0] * t, point[0], 1e-9);
  EXPECT_NEAR(p->start[1] + p->velocity[1] * t, point[1], 1e-9);
  EXPECT_NEAR(p->start[2] + p->velocity[2] * t - 0.5 * g * t * t, point[2], 1e-9);
  EXPECT_LT(p->velocity[2] - g * t, 0);
  EXPECT_LT(p->meet_s, p->arrival_s);
  // Advanced to the meeting, the pass starts at the point; its times shrink by as much.
  const Pass at = AdvancePass(*p, t, g, 0.9);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(at.start[c], point[c], 1e-9) << c;
  EXPECT_NEAR(at.meet_s, 0, 1e-12);
  EXPECT_NEAR(at.arrival_s, p->arrival_s - t, 1e-12);
  // A point above the flight's apex is refused.
  const double high[3] = {0.4, 0, 20};
  EXPECT_EQ(LobPassThrough(high, M_PI, 12, 50, 0.13, r, g).status().code(),
            absl::StatusCode::kFailedPrecondition);
}

TEST(PassThroughTest, AdvancingAGroundPassRollsItToItsAimAtItsArrivalSpeed) {
  const double aim[2] = {0.4, 0.1};
  const Pass p = GroundPassArrivingAt(aim, M_PI + 0.3, 3, 12, 0.9, 0.11);
  const Pass at = AdvancePass(p, p.arrival_s, 9.81, 0.9);
  EXPECT_NEAR(at.start[0], aim[0], 1e-9);
  EXPECT_NEAR(at.start[1], aim[1], 1e-9);
  EXPECT_NEAR(std::hypot(at.velocity[0], at.velocity[1]), 3, 1e-9);
  EXPECT_NEAR(at.start[2], 0.11, 1e-12);
}

}  // namespace
}  // namespace juggle::football

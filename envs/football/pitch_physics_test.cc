// The football pitch model (configs/models/football_pitch.xml, docs/football.md "The pitch"):
// the ball on the turf against the analytic roll of a hollow ball under rolling resistance, its
// bounce against the restitution its solref was designed for and FIFA's turf range, one
// contact per ball on the turf, and the goal frame stopping the ball.
#include <cmath>
#include <string>

#include <mujoco/mujoco.h>

#include "envs/mujoco_model.h"
#include "envs/testing/test_configs.h"
#include "gtest/gtest.h"

namespace juggle {
namespace {

class PitchPhysicsTest : public ::testing::Test {
 protected:
  void SetUp() override {
    absl::StatusOr<MjModelPtr> model =
        LoadModelXml(testing::RepoPath("configs/models/football_pitch.xml"), "test");
    ASSERT_TRUE(model.ok()) << model.status();
    model_ = *std::move(model);
    m_ = model_.get();
    data_.reset(mj_makeData(m_));
    d_ = data_.get();
    ball_body_ = mj_name2id(m_, mjOBJ_BODY, "ball");
    ball_geom_ = mj_name2id(m_, mjOBJ_GEOM, "ball");
    pitch_geom_ = mj_name2id(m_, mjOBJ_GEOM, "pitch");
    ASSERT_GE(ball_body_, 0);
    ASSERT_GE(ball_geom_, 0);
    ASSERT_GE(pitch_geom_, 0);
    const int joint = m_->body_jntadr[ball_body_];
    ball_qpos_ = m_->jnt_qposadr[joint];
    ball_dof_ = m_->jnt_dofadr[joint];
    radius_ = m_->geom_size[3 * ball_geom_];
  }

  // The ball alone at (x, y, z) (its centre), at rest, far from the standing character.
  void PlaceBall(double x, double y, double z) {
    mj_resetData(m_, d_);
    double* q = d_->qpos + ball_qpos_;
    q[0] = x;
    q[1] = y;
    q[2] = z;
    q[3] = 1;
    q[4] = q[5] = q[6] = 0;
    mj_forward(m_, d_);
  }
  // Lets the ball settle on the turf at (x, y).
  void SettleBall(double x, double y) {
    PlaceBall(x, y, radius_);
    for (int i = 0; i < 400; ++i) mj_step(m_, d_);
  }
  double* ball_pos() { return d_->qpos + ball_qpos_; }
  double* ball_vel() { return d_->qvel + ball_dof_; }
  int BallContacts(int* with_pitch) const {
    int n = 0;
    *with_pitch = 0;
    for (int i = 0; i < d_->ncon; ++i) {
      const mjContact& c = d_->contact[i];
      if (c.geom1 != ball_geom_ && c.geom2 != ball_geom_) continue;
      ++n;
      if (c.geom1 == pitch_geom_ || c.geom2 == pitch_geom_) ++*with_pitch;
    }
    return n;
  }

  MjModelPtr model_;
  MjDataPtr data_;
  const mjModel* m_ = nullptr;
  mjData* d_ = nullptr;
  int ball_body_ = -1, ball_geom_ = -1, pitch_geom_ = -1;
  int ball_qpos_ = 0, ball_dof_ = 0;
  double radius_ = 0;
};

TEST_F(PitchPhysicsTest, TheBallOnTheTurfIsOneContactWithThePairsRollingFriction) {
  SettleBall(3, 0);
  int with_pitch = 0;
  EXPECT_EQ(BallContacts(&with_pitch), 1);
  ASSERT_EQ(with_pitch, 1) << "the explicit pair only, not also a dynamic contact";
  const int pair = mj_name2id(m_, mjOBJ_PAIR, "ball_on_turf");
  ASSERT_GE(pair, 0);
  for (int i = 0; i < d_->ncon; ++i) {
    const mjContact& c = d_->contact[i];
    if (c.geom1 != ball_geom_ && c.geom2 != ball_geom_) continue;
    EXPECT_EQ(c.dim, 6);
    EXPECT_DOUBLE_EQ(c.friction[3], m_->pair_friction[5 * pair + 3]);
  }
  EXPECT_NEAR(ball_pos()[2], radius_, 1e-3);
}

TEST_F(PitchPhysicsTest, ARolledBallStopsWhereItsRollingResistanceSays) {
  // A hollow ball rolling without slipping under a rolling-resistance torque μ_r·N decelerates
  // at a = μ_r·g / (r·(1 + I/(m·r²))); from v0 it rolls v0² / (2a). Every number from the model.
  const int pair = mj_name2id(m_, mjOBJ_PAIR, "ball_on_turf");
  const double mu_roll = m_->pair_friction[5 * pair + 3];
  const double mass = m_->body_mass[ball_body_];
  const double inertia = m_->body_inertia[3 * ball_body_];
  const double g = -m_->opt.gravity[2];
  const double a = mu_roll * g / (radius_ * (1 + inertia / (mass * radius_ * radius_)));
  EXPECT_NEAR(a, 0.90, 0.01) << "the documented deceleration";
  for (double v0 : {2.0, 5.0, 10.0}) {
    SCOPED_TRACE(v0);
    SettleBall(0, 20);  // beside the character, out of its reach
    const double x0 = ball_pos()[0];
    ball_vel()[0] = v0;
    ball_vel()[4] = v0 / radius_;  // rolling: ω_y = v / r
    int steps = 0;
    while (std::hypot(ball_vel()[0], ball_vel()[1]) > 0.005 && steps < 200000) {
      mj_step(m_, d_);
      ++steps;
    }
    const double rolled = ball_pos()[0] - x0;
    const double analytic = v0 * v0 / (2 * a);
    // MuJoCo's soft rolling constraint resists about 2.5 % less than the rigid formula
    // (docs/football.md): within 4 %.
    EXPECT_NEAR(rolled / analytic, 1.0, 0.04) << rolled << " m rolled, " << analytic << " m analytic";
    EXPECT_NEAR(ball_pos()[1], 20, 1e-3) << "a straight roll";
  }
}

TEST_F(PitchPhysicsTest, AfterItsFirstSecondARollingBallSlowsAtTheFormulasRate) {
  // In its first second a roll started without slip decelerates less (MuJoCo's soft friction
  // builds a steady slip of about 4 % of the speed); from then on, at the rigid formula's rate.
  const int pair = mj_name2id(m_, mjOBJ_PAIR, "ball_on_turf");
  const double mu_roll = m_->pair_friction[5 * pair + 3];
  const double k = m_->body_inertia[3 * ball_body_] /
                   (m_->body_mass[ball_body_] * radius_ * radius_);
  const double a = mu_roll * -m_->opt.gravity[2] / (radius_ * (1 + k));
  SettleBall(0, 20);
  ball_vel()[0] = 8.7;
  ball_vel()[4] = 8.7 / radius_;
  const int second = static_cast<int>(std::lround(1.0 / m_->opt.timestep));
  for (int i = 0; i < second; ++i) mj_step(m_, d_);
  const double v1 = ball_vel()[0], x1 = ball_pos()[0];
  for (int i = 0; i < 6 * second; ++i) mj_step(m_, d_);
  const double v7 = ball_vel()[0], x7 = ball_pos()[0];
  EXPECT_NEAR((v1 - v7) / 6.0 / a, 1.0, 0.02) << "by speed";
  EXPECT_NEAR((v1 * v1 - v7 * v7) / (2 * (x7 - x1)) / a, 1.0, 0.02) << "by distance";
}

TEST_F(PitchPhysicsTest, ADropFromTwoMetresReboundsAsTheSolrefSaysAndWithinFifaTurfRange) {
  // The direct solref (−K, −D) is a damped spring: ζ = D / (2√K), restitution
  // e = exp(−πζ / √(1 − ζ²)); a drop from h rebounds to e²·h.
  const int pair = mj_name2id(m_, mjOBJ_PAIR, "ball_on_turf");
  const double k = -m_->pair_solref[mjNREF * pair];
  const double damping = -m_->pair_solref[mjNREF * pair + 1];
  const double zeta = damping / (2 * std::sqrt(k));
  const double e = std::exp(-M_PI * zeta / std::sqrt(1 - zeta * zeta));
  PlaceBall(0, 20, 2.0 + radius_);
  bool rising = false;
  double apex = 0;
  for (int i = 0; i < 4000; ++i) {
    mj_step(m_, d_);
    if (ball_vel()[2] > 0) rising = true;
    if (rising) {
      apex = std::max(apex, ball_pos()[2] - radius_);
      if (ball_vel()[2] < 0) break;
    }
  }
  ASSERT_TRUE(rising) << "the ball never left the turf";
  EXPECT_NEAR(std::sqrt(apex / 2.0), e, 0.02) << "rebound " << apex << " m";
  // FIFA Quality Pro football turf: a 2 m drop rebounds 0.60-0.85 m.
  EXPECT_GE(apex, 0.60);
  EXPECT_LE(apex, 0.85);
}

TEST_F(PitchPhysicsTest, TheGoalFrameStopsARolledBallAndTheCharacterStandsOnTheTurf) {
  // Rolled straight at the left post: it comes back.
  SettleBall(8, 3.72);
  ball_vel()[0] = 8;
  ball_vel()[4] = 8 / radius_;
  bool hit_post = false;
  const int post = mj_name2id(m_, mjOBJ_GEOM, "goal_left_post");
  for (int i = 0; i < 2000 && !hit_post; ++i) {
    mj_step(m_, d_);
    for (int c = 0; c < d_->ncon; ++c) {
      hit_post |= (d_->contact[c].geom1 == post || d_->contact[c].geom2 == post);
    }
  }
  ASSERT_TRUE(hit_post);
  for (int i = 0; i < 40; ++i) mj_step(m_, d_);
  EXPECT_LT(ball_vel()[0], 0) << "the post sends it back";
  EXPECT_LT(ball_pos()[0], 11.06 - 0.06 - radius_ + 0.02) << "it did not pass through";
  // The feet touch the turf (the character's bits meet the pitch's).
  mj_resetData(m_, d_);
  mj_forward(m_, d_);
  for (int i = 0; i < 200; ++i) mj_step(m_, d_);
  const int right_foot = mj_name2id(m_, mjOBJ_GEOM, "right_foot");
  bool foot_on_turf = false;
  for (int c = 0; c < d_->ncon; ++c) {
    const mjContact& contact = d_->contact[c];
    foot_on_turf |= (contact.geom1 == right_foot && contact.geom2 == pitch_geom_) ||
                    (contact.geom2 == right_foot && contact.geom1 == pitch_geom_);
  }
  EXPECT_TRUE(foot_on_turf);
}

}  // namespace
}  // namespace juggle

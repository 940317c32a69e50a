// Test fixture: the shipped pitch model (configs/models/football_pitch.xml) with its ball found,
// and the ball placed, launched and read in it.
#ifndef JUGGLE_ENVS_FOOTBALL_TESTING_PITCH_FIXTURE_H_
#define JUGGLE_ENVS_FOOTBALL_TESTING_PITCH_FIXTURE_H_

#include <mujoco/mujoco.h>

#include <algorithm>
#include <optional>

#include "envs/football/pitch.h"
#include "envs/mujoco_model.h"
#include "envs/testing/test_configs.h"
#include "gtest/gtest.h"

namespace juggle::football::testing {

class PitchFixture : public ::testing::Test {
 protected:
  void SetUp() override {
    absl::StatusOr<MjModelPtr> model =
        LoadModelXml(juggle::testing::RepoPath("configs/models/football_pitch.xml"), "test");
    ASSERT_TRUE(model.ok()) << model.status();
    model_ = *std::move(model);
    m_ = model_.get();
    data_.reset(mj_makeData(m_));
    d_ = data_.get();
    absl::StatusOr<PitchBall> ball = FindPitchBall(m_);
    ASSERT_TRUE(ball.ok()) << ball.status();
    ball_ = *ball;
    radius_ = ball_.radius;
    g_ = -m_->opt.gravity[2];
  }

  // A fresh state with the ball's centre at (x, y, z), at rest (the character as the model has
  // it: far passes leave it out of reach).
  void PlaceBall(double x, double y, double z) {
    mj_resetData(m_, d_);
    double* q = d_->qpos + ball_.qpos;
    q[0] = x;
    q[1] = y;
    q[2] = z;
    q[3] = 1;
    q[4] = q[5] = q[6] = 0;
    mj_forward(m_, d_);
  }
  // The ball settled on the turf at (x, y).
  void SettleBall(double x, double y) {
    PlaceBall(x, y, radius_);
    for (int i = 0; i < 400; ++i) mj_step(m_, d_);
  }
  // Rolling without slipping at horizontal velocity (vx, vy): ω = ẑ × v / r.
  void Roll(double vx, double vy) {
    double* v = ball_vel();
    v[0] = vx;
    v[1] = vy;
    v[3] = -vy / radius_;
    v[4] = vx / radius_;
  }
  // Steps a ball dropped from rest until it has rebounded and starts to fall again: the height
  // of its lowest point above `surface_z` at that apex, or nullopt when it never rose within
  // 10 simulated seconds.
  std::optional<double> ReboundApex(double surface_z) {
    bool rising = false;
    double apex = 0;
    for (int i = 0; i < 4000; ++i) {
      mj_step(m_, d_);
      if (ball_vel()[2] > 0) rising = true;
      if (rising) {
        apex = std::max(apex, ball_pos()[2] - radius_ - surface_z);
        if (ball_vel()[2] < 0) break;
      }
    }
    if (!rising) return std::nullopt;
    return apex;
  }
  double* ball_pos() { return d_->qpos + ball_.qpos; }
  double* ball_vel() { return d_->qvel + ball_.dof; }
  // Whether a contact of `d_` joins geoms a and b (either order).
  bool Touching(int a, int b) const {
    for (int i = 0; i < d_->ncon; ++i) {
      const mjContact& c = d_->contact[i];
      if ((c.geom1 == a && c.geom2 == b) || (c.geom1 == b && c.geom2 == a)) return true;
    }
    return false;
  }

  MjModelPtr model_;
  MjDataPtr data_;
  const mjModel* m_ = nullptr;
  mjData* d_ = nullptr;
  PitchBall ball_;
  double radius_ = 0, g_ = 0;
};

}  // namespace juggle::football::testing

#endif  // JUGGLE_ENVS_FOOTBALL_TESTING_PITCH_FIXTURE_H_
